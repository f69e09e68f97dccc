#include "dc/engine/internal_body_order.hpp"

#include <algorithm>
#include <string>
#include <type_traits>

#include "dc/core/error.hpp"
#include "world/spatial_order.hpp"

namespace dc {
namespace {

/// v ← (v[order[0]], v[order[1]], …) through `scratch` (no allocation after the first call).
template <class T>
void permute(std::vector<T>& v, const std::vector<int>& order, std::vector<T>& scratch) {
  scratch.resize(v.size());
  for (std::size_t i = 0; i < order.size(); ++i) scratch[i] = v[static_cast<std::size_t>(order[i])];
  v.swap(scratch);
}

/// Calls f(field of a, field of b) for every per-body array of two body states.
template <class F>
void for_each_field(BodyState& a, const BodyState& b, F&& f) {
  f(a.position, b.position);
  f(a.angle, b.angle);
  f(a.velocity, b.velocity);
  f(a.omega, b.omega);
  f(a.radius, b.radius);
  f(a.density, b.density);
  f(a.mass, b.mass);
  f(a.inertia, b.inertia);
  f(a.inv_mass, b.inv_mass);
  f(a.inv_inertia, b.inv_inertia);
}

}  // namespace

void InternalBodyOrder::update_from(const BodyState& external, bool copy_all) {
  if (!external.shapes.empty())
    throw ConfigError("[bodies] internal_order = \"morton\" is for circle-only scenes (no shapes, static or "
                          "kinematic bodies)");
  const std::size_t old_n = state_.size(), n = external.size();
  if (n < old_n)
    throw InvalidArgument("World: the body state lost bodies (" + std::to_string(old_n) + " -> " +
                          std::to_string(n) + "); bodies can only be appended");
  for (std::size_t k = old_n; k < n; ++k) external_of_.push_back(static_cast<int>(k));
  const std::size_t from = copy_all ? 0 : old_n;
  for_each_field(state_, external, [&](auto& mine, const auto& theirs) {
    mine.resize(n);
    for (std::size_t i = from; i < n; ++i) mine[i] = theirs[static_cast<std::size_t>(external_of_[i])];
  });
}

void InternalBodyOrder::resort(double cell) {
  const std::vector<int> order = morton_order(state_.position, cell);
  std::vector<Vec2> vec_scratch;
  std::vector<double> scalar_scratch;
  for_each_field(state_, state_, [&](auto& field, const auto&) {
    if constexpr (std::is_same_v<std::decay_t<decltype(field)>, std::vector<Vec2>>)
      permute(field, order, vec_scratch);
    else
      permute(field, order, scalar_scratch);
  });
  std::vector<int> int_scratch;
  permute(external_of_, order, int_scratch);
}

void InternalBodyOrder::gather_kinematics(BodyState& external) const {
  for (std::size_t i = 0; i < external_of_.size(); ++i) {
    const auto k = static_cast<std::size_t>(external_of_[i]);
    external.position[k] = state_.position[i];
    external.angle[k] = state_.angle[i];
    external.velocity[k] = state_.velocity[i];
    external.omega[k] = state_.omega[i];
  }
}

void InternalBodyOrder::contacts_to_external(const std::vector<Contact>& internal, int bodies,
                                             std::vector<Contact>& external) {
  const std::size_t m = internal.size();
  keys_.resize(m);
  flipped_.assign(m, 0);
  // Keys' first index ranges over the walls (−4 … −1) and the bodies: bucket a + 4.
  constexpr int kWallOffset = 4;
  bucket_start_.assign(static_cast<std::size_t>(bodies + kWallOffset + 1), 0);
  for (std::size_t i = 0; i < m; ++i) {
    const Contact& c = internal[i];
    const int b = external_of_[static_cast<std::size_t>(c.body_b)];
    if (c.body_a < 0) {
      keys_[i] = ContactKey{c.key.a, b, c.key.feature};
    } else {
      const int a = external_of_[static_cast<std::size_t>(c.body_a)];
      keys_[i] = ContactKey::pair(a, b, c.key.feature);
      flipped_[i] = a > b;
    }
    ++bucket_start_[static_cast<std::size_t>(keys_[i].a + kWallOffset + 1)];
  }
  for (std::size_t k = 1; k < bucket_start_.size(); ++k) bucket_start_[k] += bucket_start_[k - 1];
  sorted_.resize(m);
  for (std::size_t i = 0; i < m; ++i)
    sorted_[static_cast<std::size_t>(bucket_start_[static_cast<std::size_t>(keys_[i].a + kWallOffset)]++)] =
        static_cast<int>(i);
  // bucket_start_[k] now holds the end of bucket k: sort each bucket by the whole key.
  auto by_key = [&](int x, int y) { return keys_[static_cast<std::size_t>(x)] < keys_[static_cast<std::size_t>(y)]; };
  int begin = 0;
  for (const int end : bucket_start_) {
    if (end - begin > 1) std::sort(sorted_.begin() + begin, sorted_.begin() + end, by_key);
    begin = end;
  }
  external.resize(m);
  internal_of_contact_.resize(m);
  for (std::size_t c = 0; c < m; ++c) {
    const auto i = static_cast<std::size_t>(sorted_[c]);
    Contact e = internal[i];
    e.key = keys_[i];
    e.body_a = e.key.a;
    e.body_b = e.key.b;
    if (flipped_[i]) {
      e.normal = -e.normal;  // t = perp(n) turns too; λ_t along it is the same number
      std::swap(e.anchor_a, e.anchor_b);
    }
    external[c] = e;
    internal_of_contact_[c] = static_cast<int>(i);
  }
}

void InternalBodyOrder::rows_to_internal(const ContactConstraints& external, const ContactConstraints& internal,
                                         const Eigen::VectorXd& lambda_external,
                                         Eigen::VectorXd& lambda_internal) const {
  lambda_internal.setZero(internal.rows());
  for (int c = 0; c < external.size(); ++c) {
    const ContactConstraint& e = external[c];
    const ContactConstraint& i = internal[internal_contact(c)];
    lambda_internal[i.normal_row] = lambda_external[e.normal_row];
    if (e.tangent_row >= 0)
      lambda_internal[i.tangent_row] = lambda_external[e.tangent_row];
  }
}

void InternalBodyOrder::rows_to_external(const ContactConstraints& external, const ContactConstraints& internal,
                                         const Eigen::VectorXd& lambda_internal,
                                         Eigen::VectorXd& lambda_external) const {
  lambda_external.setZero(external.rows());
  for (int c = 0; c < external.size(); ++c) {
    const ContactConstraint& e = external[c];
    const ContactConstraint& i = internal[internal_contact(c)];
    lambda_external[e.normal_row] = lambda_internal[i.normal_row];
    if (e.tangent_row >= 0)
      lambda_external[e.tangent_row] = lambda_internal[i.tangent_row];
  }
}

}  // namespace dc
