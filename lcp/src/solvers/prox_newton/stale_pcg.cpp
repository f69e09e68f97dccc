#include "solvers/prox_newton/stale_pcg.hpp"

#include <cmath>

namespace dc::solvers::prox {

PcgOutcome pcg(const LinearMap& H, const LinearMap& P_inverse, const Eigen::VectorXd& b, Eigen::VectorXd& x,
               int max_iterations, double tolerance) {
  PcgOutcome out;
  Eigen::VectorXd r = b, z, p, hp;
  P_inverse(r, z);
  const double rz0 = dot_in_order(r, z);
  x = z;  // the first iterate: the stale factor's own solve (exact when H = H_old)
  if (!(rz0 > 0) || !std::isfinite(rz0)) {
    out.converged = rz0 == 0;
    return out;
  }
  H(x, hp);
  r -= hp;
  P_inverse(r, z);
  double rz = dot_in_order(r, z);
  const double stop = tolerance * tolerance * rz0;
  p = z;
  while (true) {
    if (!(rz > stop)) {
      out.converged = std::isfinite(rz);
      return out;
    }
    if (out.iterations >= max_iterations) return out;
    ++out.iterations;
    H(p, hp);
    const double php = dot_in_order(p, hp);
    if (!(php > 0) || !std::isfinite(php)) return out;
    const double alpha = rz / php;
    x += alpha * p;
    r -= alpha * hp;
    P_inverse(r, z);
    const double next = dot_in_order(r, z);
    p = z + (next / rz) * p;
    rz = next;
  }
}

}  // namespace dc::solvers::prox
