#include "dc/lcp/contact_constraints.hpp"

#include <cmath>
#include <string>

#include "dc/core/error.hpp"
#include "dc/core/number_text.hpp"

namespace dc {

int ContactConstraints::add(const ContactConstraint& k) {
  const int c = add(k.body_a, k.body_b, k.mu, k.feature);
  if (k.normal_row < 0 || (k.tangent_row >= 0) != (k.mu > 0)) {
    contacts_.pop_back();
    rows_ -= k.mu > 0 ? 2 : 1;
    throw InvalidArgument("ContactConstraints::add: contact " + std::to_string(c) +
                          " needs a normal row, and a tangent row exactly when mu > 0");
  }
  contacts_.back().normal_row = k.normal_row;
  contacts_.back().tangent_row = k.tangent_row;
  return c;
}

void ContactConstraints::check(int c, int body_a, int body_b, double mu) {
  const bool bodies_ok = body_b >= 0 && body_a >= -1 && body_a != body_b;
  if (bodies_ok && mu >= 0 && std::isfinite(mu)) return;
  std::string what = "ContactConstraints::add: contact " + std::to_string(c);
  if (!bodies_ok)
    throw InvalidArgument(what.append(" has bodies (")
                              .append(std::to_string(body_a))
                              .append(", ")
                              .append(std::to_string(body_b))
                              .append("); need body_b >= 0 and body_a = -1 or another body"));
  if (!(mu >= 0) || !std::isfinite(mu))
    throw InvalidArgument(what.append(" has friction coefficient ").append(g_text(mu)).append("; need a finite mu >= 0"));
}

int ContactConstraints::add(int body_a, int body_b, double mu, int feature) {
  if (!valid(body_a, body_b, mu)) check(static_cast<int>(contacts_.size()), body_a, body_b, mu);  // throws
  ContactConstraint& k = contacts_.emplace_back();
  k.body_a = body_a;
  k.body_b = body_b;
  k.mu = mu;
  k.feature = feature;
  k.normal_row = rows_++;
  if (mu > 0) k.tangent_row = rows_++;
  return static_cast<int>(contacts_.size()) - 1;
}

void ContactConstraints::clear() {
  contacts_.clear();
  rows_ = 0;
}

void ContactConstraints::reserve(std::size_t contacts) { contacts_.reserve(contacts); }

std::span<ContactConstraint> ContactConstraints::overwrite(std::size_t contacts, int rows) {
  contacts_.resize(contacts);
  rows_ = rows;
  return contacts_;
}

Eigen::VectorXd ContactConstraints::scatter(std::span<const double> pairs) const {
  if (pairs.size() != 2 * contacts_.size())
    throw InvalidArgument("ContactConstraints::scatter: " + std::to_string(pairs.size()) + " values for " +
                          std::to_string(contacts_.size()) + " contacts (expected 2 each)");
  Eigen::VectorXd out(rows_);
  for (int c = 0; c < size(); ++c)
    put(c, pairs[2 * static_cast<std::size_t>(c)], pairs[2 * static_cast<std::size_t>(c) + 1], out);
  return out;
}

Eigen::VectorXd ContactConstraints::scatter(std::span<const double> lambda_n, std::span<const double> lambda_t) const {
  bool any_tangent = false;
  for (const ContactConstraint& k : contacts_) any_tangent = any_tangent || k.has_friction();
  if (lambda_n.size() != contacts_.size() || (any_tangent && lambda_t.size() != contacts_.size()) ||
      (!lambda_t.empty() && lambda_t.size() != contacts_.size()))
    throw InvalidArgument("ContactConstraints::scatter: need one lambda_n (and lambda_t) per contact; got " +
                          std::to_string(lambda_n.size()) + " and " + std::to_string(lambda_t.size()) + " for " +
                          std::to_string(contacts_.size()) + " contacts");
  Eigen::VectorXd out(rows_);
  for (int c = 0; c < size(); ++c) {
    const auto u = static_cast<std::size_t>(c);
    put(c, lambda_n[u], lambda_t.empty() ? 0.0 : lambda_t[u], out);
  }
  return out;
}

void ContactConstraints::gather(const Eigen::VectorXd& lambda, std::vector<double>& pairs) const {
  if (lambda.size() != rows_)
    throw InvalidArgument("ContactConstraints::gather: lambda has " + std::to_string(lambda.size()) +
                          " entries, the contacts own " + std::to_string(rows_) + " rows");
  pairs.resize(2 * contacts_.size());
  for (int c = 0; c < size(); ++c) {
    pairs[2 * static_cast<std::size_t>(c)] = lambda_n(lambda, c);
    pairs[2 * static_cast<std::size_t>(c) + 1] = lambda_t(lambda, c);
  }
}

std::vector<double> ContactConstraints::gather(const Eigen::VectorXd& lambda) const {
  std::vector<double> out;
  gather(lambda, out);
  return out;
}

}  // namespace dc
