#pragma once
// The builtin warm start written out over a World's public views, for the engine's tests (the
// warmstart library sits above the engine): the previous step's λ of the contact with the same
// key, 0 for new contacts, in the rows of problem(), not projected.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "dc/engine/world.hpp"

namespace dc::test {

inline Eigen::VectorXd previous_lambda_by_key(const World& w) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(w.problem().rows());
  const std::vector<int> match = match_contacts_by_key(w.previous_contacts(), w.contacts());
  for (std::size_t c = 0; c < match.size(); ++c)
    if (match[c] >= 0) {
      const Contact& p = w.previous_contacts()[static_cast<std::size_t>(match[c])];
      w.constraints().put(static_cast<int>(c), p.lambda_n, p.lambda_t, out);
    }
  return out;
}

}  // namespace dc::test
