#include "dc/engine/internal_body_order.hpp"

#include <algorithm>
#include <cstdlib>
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
    throw ConfigError("[bodies] internal_order: the Morton internal order is for circle-only scenes (no shapes, "
                          "static or kinematic bodies; \"none\" steps them)");
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
  new_of_old_.resize(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) new_of_old_[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
}

void InternalBodyOrder::rekey(std::vector<Contact>& contacts) const {
  const auto moved = [&](int i) { return new_of_old_[static_cast<std::size_t>(i)]; };
  for (Contact& c : contacts) {
    const int b = moved(c.body_b);
    if (c.body_a < 0) {
      c.key = ContactKey{c.key.a, b, c.key.feature};
    } else {
      const int a = moved(c.body_a);
      c.key = ContactKey::pair(a, b, c.key.feature);
      if (a > b) {  // the pair's bodies changed order: turn the contact as contacts_to_external does
        c.normal = -c.normal;
        std::swap(c.anchor_a, c.anchor_b);
      }
    }
    c.body_a = c.key.a;
    c.body_b = c.key.b;
  }
  std::sort(contacts.begin(), contacts.end(), [](const Contact& x, const Contact& y) { return x.key < y.key; });
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

Contact InternalBodyOrder::external_contact(const Contact& internal) const {
  Contact e = internal;
  const int b = external_of_[static_cast<std::size_t>(internal.body_b)];
  if (internal.body_a < 0) {
    e.key = ContactKey{internal.key.a, b, internal.key.feature};
  } else {
    const int a = external_of_[static_cast<std::size_t>(internal.body_a)];
    e.key = ContactKey::pair(a, b, internal.key.feature);
    if (a > b) {
      e.normal = -e.normal;  // t = perp(n) turns too; λ_t along it is the same number
      std::swap(e.anchor_a, e.anchor_b);
    }
  }
  e.body_a = e.key.a;
  e.body_b = e.key.b;
  return e;
}

void InternalBodyOrder::external_order(const std::vector<Contact>& internal, int bodies,
                                       std::vector<int>& internal_of) const {
  const std::size_t m = internal.size();
  keys_.resize(m);
  ContactKey* const keys = keys_.data();
  const int* const ext = external_of_.data();
  for (std::size_t i = 0; i < m; ++i) {
    const Contact& c = internal[i];
    const int b = ext[c.body_b];
    keys[i] = c.body_a < 0 ? ContactKey{c.key.a, b, c.key.feature} : ContactKey::pair(ext[c.body_a], b, c.key.feature);
  }
  sort_by_keys(bodies, internal_of);
}

void InternalBodyOrder::external_order(const std::vector<Contact>& internal, const ContactConstraints& assembled,
                                       int bodies, std::vector<int>& internal_of) const {
  if (assembled.size() != static_cast<int>(internal.size()))
    throw InvalidArgument("InternalBodyOrder::external_order: " + std::to_string(assembled.size()) +
                          " constraints for " + std::to_string(internal.size()) + " contacts");
  // The constraints hold body_a (−1 for a wall), body_b and the feature of each contact in a
  // quarter of a Contact's bytes: only a wall contact's record is read, for its wall id.
  const std::size_t m = internal.size();
  keys_.resize(m);
  ContactKey* const keys = keys_.data();
  const int* const ext = external_of_.data();
  const ContactConstraint* const k = m > 0 ? &assembled[0] : nullptr;
  for (std::size_t i = 0; i < m; ++i) {
    const ContactConstraint& kc = k[i];
    const int b = ext[kc.body_b];
    keys[i] = kc.body_a < 0 ? ContactKey{internal[i].key.a, b, kc.feature} : ContactKey::pair(ext[kc.body_a], b, kc.feature);
  }
  sort_by_keys(bodies, internal_of);
}

void InternalBodyOrder::sort_by_keys(int bodies, std::vector<int>& internal_of) const {
  const std::size_t m = keys_.size();
  const ContactKey* const keys = keys_.data();
  // Keys' first index ranges over the walls (−4 … −1) and the bodies: bucket a + 4.
  constexpr int kWallOffset = 4;
  bucket_start_.assign(static_cast<size_t>(bodies + kWallOffset + 1), 0);
  int* const start = bucket_start_.data();
  for (std::size_t i = 0; i < m; ++i) ++start[keys[i].a + kWallOffset + 1];
  for (std::size_t k = 1; k < bucket_start_.size(); ++k) start[k] += start[k - 1];
  sorted_.resize(m);
  int* const sorted = sorted_.data();
  for (std::size_t i = 0; i < m; ++i) sorted[start[keys[i].a + kWallOffset]++] = static_cast<int>(i);
  // bucket_start_[k] now holds the end of bucket k: sort each bucket by the whole key.
  auto by_key = [&](int x, int y) { return keys[x] < keys[y]; };
  int begin = 0;
  for (const int end : bucket_start_) {
    if (end - begin > 1) std::sort(sorted + begin, sorted + end, by_key);
    begin = end;
  }
  internal_of.swap(sorted_);  // the result, without a copy; the old vector is the next call's scratch
}

void InternalBodyOrder::contacts_to_external(const std::vector<Contact>& internal, const std::vector<int>& internal_of,
                                             std::vector<Contact>& external) const {
  external.resize(internal_of.size());
  for (std::size_t c = 0; c < internal_of.size(); ++c)
    external[c] = external_contact(internal[static_cast<std::size_t>(internal_of[c])]);
}

void InternalBodyOrder::bodies_for_assembly(const std::vector<Vec2>& position, const std::vector<Vec2>& velocity,
                                            const std::vector<double>& omega, BodyState& external) const {
  const std::size_t n = external_of_.size();
  external.position.resize(n);
  external.velocity.resize(n);
  external.omega.resize(n);
  external.inv_mass.resize(n);
  external.inv_inertia.resize(n);
  external.shapes = {};
  for (std::size_t i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(external_of_[i]);
    external.position[k] = position[i];
    external.velocity[k] = velocity[i];
    external.omega[k] = omega[i];
    external.inv_mass[k] = state_.inv_mass[i];
    external.inv_inertia[k] = state_.inv_inertia[i];
  }
}

void InternalBodyOrder::rows_to_internal(const ContactConstraints& external, const ContactConstraints& internal,
                                         const std::vector<int>& internal_of, const Eigen::Ref<const Eigen::VectorXd>& lambda_external,
                                         Eigen::VectorXd& lambda_internal) {
  lambda_internal.setZero(internal.rows());
  for (int c = 0; c < external.size(); ++c) {
    const ContactConstraint& e = external[c];
    const ContactConstraint& i = internal[internal_of[static_cast<std::size_t>(c)]];
    lambda_internal[i.normal_row] = lambda_external[e.normal_row];
    if (e.tangent_row >= 0)
      lambda_internal[i.tangent_row] = lambda_external[e.tangent_row];
  }
}

void InternalBodyOrder::rows_to_external(const ContactConstraints& internal, const std::vector<int>& internal_of,
                                         const Eigen::Ref<const Eigen::VectorXd>& lambda_internal, Eigen::VectorXd& lambda_external) {
  lambda_external.resize(internal.rows());
  Eigen::Index row = 0;  // external rows: contact by contact, normal then tangent
  for (const int c : internal_of) {
    const ContactConstraint& i = internal[c];
    lambda_external[row++] = lambda_internal[i.normal_row];
    if (i.tangent_row >= 0) lambda_external[row++] = lambda_internal[i.tangent_row];
  }
}

InternalBodyOrder::Spread InternalBodyOrder::pair_spread(const std::vector<Contact>& internal) {
  Spread s;
  for (const Contact& c : internal)
    if (c.body_a >= 0) {
      s.sum += std::abs(c.body_b - c.body_a);
      ++s.pairs;
    }
  return s;
}

}  // namespace dc
