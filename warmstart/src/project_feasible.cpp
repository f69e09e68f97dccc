#include <algorithm>
#include <cmath>

#include "dc/core/error.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

void project_feasible(const LcpProblem& p, Eigen::VectorXd& lambda) {
  if (lambda.size() != p.rows())
    throw InvalidArgument("project_feasible: λ has " + std::to_string(lambda.size()) +
                          " entries, the problem has " + std::to_string(p.rows()) + " rows");
  // Normal (fixed-bound) rows first, then friction rows whose bounds depend on them.
  for (int i = 0; i < p.rows(); ++i) {
    if (!std::isfinite(lambda[i])) lambda[i] = 0.0;
    if (!p.is_friction_row(i)) lambda[i] = std::clamp(lambda[i], p.lo[i], p.hi[i]);
  }
  for (int i = 0; i < p.rows(); ++i)
    if (p.is_friction_row(i)) lambda[i] = std::clamp(lambda[i], p.lower(i, lambda), p.upper(i, lambda));
}

}  // namespace dc
