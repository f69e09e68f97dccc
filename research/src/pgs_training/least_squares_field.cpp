// G*: the least-squares grid field of one sample's exact correction (least_squares_field.hpp).
#include "dc/research/least_squares_field.hpp"

#include <cstddef>

#include "dc/core/error.hpp"

namespace dc {

namespace {

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

/// Rᵀ v in double (the read-back's adjoint accumulates into floats).
std::vector<double> adjoint(const ContactReadback& rb, const std::vector<double>& v, std::size_t n) {
  std::vector<float> g(n, 0.0f);
  rb.adjoint(v, g.data());
  return {g.begin(), g.end()};
}

}  // namespace

std::vector<float> least_squares_correction_grid(const PgsSample& s, int iterations) {
  if (iterations < 1) throw InvalidArgument("least_squares_correction_grid: iterations must be >= 1");
  if (s.lambda_star.size() != s.problem.rows() || s.lambda_prev.size() != s.problem.rows())
    throw InvalidArgument("least_squares_correction_grid: the sample needs lambda_star and lambda_prev");
  const std::size_t n = 2 * static_cast<std::size_t>(s.features.h()) * s.features.w();
  const std::size_t m = 2 * static_cast<std::size_t>(s.readback.points());
  std::vector<double> delta;
  s.problem.constraints.gather(Eigen::VectorXd(s.lambda_star - s.lambda_prev), delta);
  if (delta.size() != m) throw InvalidArgument("least_squares_correction_grid: read-back and contacts disagree");
  // CGLS on min ‖R G − δ‖ (Björck, Numerical Methods for Least Squares Problems, §7.4).
  std::vector<double> G(n, 0.0), r = delta, q(m);
  std::vector<double> sv = adjoint(s.readback, r, n), p = sv;
  double gamma = dot(sv, sv);
  const double gamma0 = gamma;
  for (int it = 0; it < iterations && gamma > 1e-24 * gamma0 && gamma > 0; ++it) {
    s.readback.forward(p.data(), q);
    const double qq = dot(q, q);
    if (!(qq > 0)) break;
    const double alpha = gamma / qq;
    for (std::size_t i = 0; i < n; ++i) G[i] += alpha * p[i];
    for (std::size_t i = 0; i < m; ++i) r[i] -= alpha * q[i];
    sv = adjoint(s.readback, r, n);
    const double g1 = dot(sv, sv);
    const double beta = g1 / gamma;
    gamma = g1;
    for (std::size_t i = 0; i < n; ++i) p[i] = sv[i] + beta * p[i];
  }
  return {G.begin(), G.end()};
}

}  // namespace dc
