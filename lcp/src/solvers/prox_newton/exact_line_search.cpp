#include "solvers/prox_newton/exact_line_search.hpp"

#include <algorithm>
#include <cmath>

namespace dc::solvers::prox {

void line_slope(const LineSearchInput& in, double t, double& slope, double& curvature) {
  const Eigen::VectorXd &y = *in.y, &e = *in.e, &lo = *in.lo, &hi = *in.hi;
  double s = in.a + t * in.q, c = in.q;
  const double inv = 1.0 / in.delta;
  for (Eigen::Index i = 0; i < y.size(); ++i) {
    if (e[i] == 0.0) continue;
    const double m = -(y[i] + t * e[i]) * inv;
    if (m > lo[i] && m < hi[i]) {
      s -= e[i] * m;
      c += e[i] * e[i] * inv;
    } else {
      s -= e[i] * (m <= lo[i] ? lo[i] : hi[i]);
    }
  }
  slope = s;
  curvature = c;
}

LineSearchResult exact_line_search(const LineSearchInput& in) {
  return minimise_along([&in](double t, double& s, double& c) { line_slope(in, t, s, c); });
}

LineSearchResult minimise_along(const SlopeFunction& line) {
  LineSearchResult r;
  double s0 = 0, c0 = 0;
  line(0.0, s0, c0);
  ++r.steps;
  if (!(s0 < 0.0)) return r;  // not a descent direction (or not finite): stay
  double lo_t = 0.0, hi_t = INFINITY, t = 1.0;
  for (int k = 0; k < 60; ++k) {
    double s = 0, c = 0;
    line(t, s, c);
    ++r.steps;
    if (!std::isfinite(s)) {
      hi_t = t;
    } else {
      if (std::abs(s) <= 1e-12 * std::abs(s0)) break;
      (s > 0 ? hi_t : lo_t) = t;
    }
    if (hi_t - lo_t <= 1e-14 * hi_t) break;
    double next = std::isfinite(s) && c > 0 ? t - s / c : NAN;
    if (!(next > lo_t && next < hi_t)) next = std::isfinite(hi_t) ? 0.5 * (lo_t + hi_t) : 2.0 * std::max(t, 1.0);
    t = next;
  }
  r.t = t;
  return r;
}

}  // namespace dc::solvers::prox
