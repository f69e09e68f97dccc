#pragma once
// The contact-like test problem of the solver micro benchmarks (micro_pgs, micro_newton): N
// circles (r = 1, ρ = 1: m = π, I = m/2) in a hexagonal pile, each touching its right and
// upper-right neighbours (≈ 2 contacts per body), floor contacts for the bottom row, friction
// on (normal row, then tangent row t = (−n_y, n_x), μ = 0.5), Δt = 0.01, every body at rest
// under gravity, so b = J (u + Δt M⁻¹ F_ext) with u = 0. A is not formed: each benchmark forms
// it the way it needs.
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"

namespace dc::bench_fixture {

/// Contact order of the pile's rows.
enum class HexPileOrder {
  Bodies,       ///< in body order, as a sorted broad phase gives them: each row shares a body
                ///< with the previous one (the Gauss–Seidel dependency chain is serial)
  Interleaved,  ///< interleaved with a stride of ~N/7: consecutive contacts touch other bodies
};

inline LcpProblem hex_pile(int bodies, HexPileOrder order = HexPileOrder::Bodies) {
  const int width = std::max(2, static_cast<int>(std::sqrt(static_cast<double>(bodies))));
  const double m = M_PI, I = 0.5 * m, dt = 0.01, mu = 0.5;
  struct C {
    int a, b;  // b = −1: floor
    double nx, ny;
  };
  std::vector<C> contacts;
  for (int k = 0; k < bodies; ++k) {
    const int row = k / width, col = k % width;
    if (row == 0) contacts.push_back({k, -1, 0.0, 1.0});
    if (col + 1 < width && k + 1 < bodies) contacts.push_back({k, k + 1, 1.0, 0.0});
    if (k + width < bodies) contacts.push_back({k, k + width, 0.5, std::sqrt(3.0) / 2});
  }
  if (order == HexPileOrder::Interleaved) {
    std::vector<C> interleaved;
    const size_t count = contacts.size(), stride = std::max<size_t>(1, count / 7);
    for (size_t start = 0; start < stride; ++start)
      for (size_t c = start; c < count; c += stride) interleaved.push_back(contacts[c]);
    contacts.swap(interleaved);
  }
  const int n = 2 * static_cast<int>(contacts.size());
  std::vector<Eigen::Triplet<double>> trip;
  LcpProblem p;
  p.b.resize(n);
  p.lo = Eigen::VectorXd::Zero(n);
  p.hi = Eigen::VectorXd::Constant(n, INFINITY);
  p.mu = Eigen::VectorXd::Zero(n);
  p.normal_row.assign(static_cast<size_t>(n), -1);
  for (size_t c = 0; c < contacts.size(); ++c) {
    const C& k = contacts[c];
    const int rn = 2 * static_cast<int>(c);
    const double tx = -k.ny, ty = k.nx;
    for (int r = 0; r < 2; ++r) {
      const double dx = r == 0 ? k.nx : tx, dy = r == 0 ? k.ny : ty;
      // r_a = n (unit radius), r_b = −n; r × d = r_x d_y − r_y d_x
      const double ca = k.nx * dy - k.ny * dx, cb = -k.nx * dy + k.ny * dx;
      if (k.b >= 0) {
        trip.emplace_back(rn + r, 3 * k.a, -dx);
        trip.emplace_back(rn + r, 3 * k.a + 1, -dy);
        trip.emplace_back(rn + r, 3 * k.a + 2, -ca);
        trip.emplace_back(rn + r, 3 * k.b, dx);
        trip.emplace_back(rn + r, 3 * k.b + 1, dy);
        trip.emplace_back(rn + r, 3 * k.b + 2, cb);
      } else {
        trip.emplace_back(rn + r, 3 * k.a, dx);
        trip.emplace_back(rn + r, 3 * k.a + 1, dy);
        trip.emplace_back(rn + r, 3 * k.a + 2, cb);
      }
    }
    p.normal_row[static_cast<size_t>(rn + 1)] = rn;
    p.mu[rn + 1] = mu;
    p.constraints.add(k.b >= 0 ? k.a : -1, k.b >= 0 ? k.b : k.a, mu);  // rows (rn, rn + 1)
  }
  p.J.resize(n, 3 * bodies);
  p.J.setFromTriplets(trip.begin(), trip.end());
  p.inv_mass.resize(3 * bodies);
  for (int k = 0; k < bodies; ++k) {
    p.inv_mass[3 * k] = p.inv_mass[3 * k + 1] = 1.0 / m;
    p.inv_mass[3 * k + 2] = 1.0 / I;
  }
  p.dt = dt;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(3 * bodies);
  for (int k = 0; k < bodies; ++k) u[3 * k + 1] = -9.81 * dt;
  p.b = p.J * u;
  return p;
}

}  // namespace dc::bench_fixture
