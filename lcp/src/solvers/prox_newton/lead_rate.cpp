#include "solvers/prox_newton/lead_rate.hpp"

#include <cmath>

namespace dc::solvers::prox {

bool LeadRate::go_on(double best, double target, int done, int chunk, int cap) {
  ++chunks_;
  const double before = chunks_ == 1 ? start_ : last_;
  if (chunks_ == 1) first_ = best;
  last_ = best;
  if (!(best < before) || !(best > 0) || !std::isfinite(best)) return false;
  if (best <= target) return false;
  const double q = chunks_ == 1 ? best / start_ : std::pow(best / first_, 1.0 / (chunks_ - 1));
  if (!(q < 1)) return false;
  const double chunks_left = std::log(target / best) / std::log(q);
  return done + chunks_left * chunk <= cap;
}

}  // namespace dc::solvers::prox
