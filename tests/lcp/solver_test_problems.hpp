#pragma once
// Random LCP problems for the solver tests (tests/engine/solver_*_test.cpp): a portable
// 64-bit generator (no std::*_distribution), SPD matrices and contact-like problems
// A = J M⁻¹ Jᵀ Δt built like the engine builds them (docs/design.md §2), and a deep resting
// pile (also timed by benchmarks/micro/micro_nncg.cpp).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cmath>
#include <cstdint>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"

namespace dc::test {

/// Solver options with an iteration cap (max_sweeps: sweeps, or Newton iterations) and every
/// other option at its default (tolerance 0: the solver's own solution test).
inline SolverOptions capped_options(int iterations = 300) {
  SolverOptions o;
  o.max_sweeps = iterations;
  return o;
}

/// splitmix64: tiny, portable, good enough for test data.
class TestRng {
 public:
  explicit TestRng(uint64_t seed) : s_(seed) {}
  uint64_t next() {
    uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform(double a = 0.0, double b = 1.0) {
    return a + (b - a) * static_cast<double>(next() >> 11) * 0x1.0p-53;
  }
  int below(int n) { return static_cast<int>(next() % static_cast<uint64_t>(n)); }

 private:
  uint64_t s_;
};

/// Random symmetric positive definite n×n matrix (well conditioned) and q with mixed signs.
inline LcpProblem random_spd(int n, TestRng& rng) {
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = rng.uniform(-1, 1);
  Eigen::MatrixXd A = B * B.transpose() + n * 0.1 * Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd q(n);
  for (int i = 0; i < n; ++i) q[i] = rng.uniform(-1, 1);
  return LcpProblem::standard(A, q);
}

/// Contact-like problem: `bodies` circles (radius 1, density 1: m = π, I = m/2), `contacts`
/// random pairs (a few against walls: one body only), a normal row per contact and, with
/// friction, a tangent row right after it coupled to it (μ = 0.5; needs μ > 0), except for
/// every `frictionless_every`-th contact (0 = none), which has μ = 0 and no tangent row.
/// A = J M⁻¹ Jᵀ Δt, Δt = 0.01. The problem carries its contact constraints, as an assembled
/// one does.
/// b = J v + s like the engine's b = J(u + Δt M⁻¹F) + speculative margin: random body
/// velocities v and a separation margin s ≥ 0 on half of the normal rows. With b in
/// range(J) + nonnegative cone the LCP is solvable even when A is rank-deficient (more
/// rows than body dofs); a random b would make such problems infeasible.
inline LcpProblem random_contact(int bodies, int contacts, bool friction, TestRng& rng, double mu = 0.5,
                                 int frictionless_every = 0) {
  auto mu_of = [&](int c) {
    return friction && !(frictionless_every > 0 && c % frictionless_every == frictionless_every - 1) ? mu : 0.0;
  };
  int n = 0;
  for (int c = 0; c < contacts; ++c) n += mu_of(c) > 0 ? 2 : 1;
  std::vector<Eigen::Triplet<double>> trip;
  LcpProblem p;
  p.b.resize(n);
  p.lo = Eigen::VectorXd::Zero(n);
  p.hi = Eigen::VectorXd::Constant(n, INFINITY);
  p.mu = Eigen::VectorXd::Zero(n);
  p.normal_row.assign(static_cast<size_t>(n), -1);
  auto cross = [](double rx, double ry, double nx, double ny) { return rx * ny - ry * nx; };
  for (int c = 0; c < contacts; ++c) {
    const int a = rng.below(bodies);
    int b = rng.below(bodies);
    const bool wall = (c % 5 == 4) || b == a;  // every 5th contact is a wall contact
    const double ang = rng.uniform(0, 2 * M_PI);
    const double nx = std::cos(ang), ny = std::sin(ang), tx = -ny, ty = nx;
    // contact point on the surface of a, in direction n: r_a = n, r_b = −n (touching circles)
    const double rax = nx + rng.uniform(-0.05, 0.05), ray = ny + rng.uniform(-0.05, 0.05);
    const double rbx = -nx, rby = -ny;
    const ContactConstraint& k = p.constraints[p.constraints.add(wall ? -1 : a, wall ? a : b, mu_of(c))];
    const int rn = k.normal_row;
    auto add_row = [&](int row, double dx, double dy) {
      if (!wall) {
        trip.emplace_back(row, 3 * a + 0, -dx);
        trip.emplace_back(row, 3 * a + 1, -dy);
        trip.emplace_back(row, 3 * a + 2, -cross(rax, ray, dx, dy));
        trip.emplace_back(row, 3 * b + 0, dx);
        trip.emplace_back(row, 3 * b + 1, dy);
        trip.emplace_back(row, 3 * b + 2, cross(rbx, rby, dx, dy));
      } else {  // wall (static) is "a", the body is b := a
        trip.emplace_back(row, 3 * a + 0, dx);
        trip.emplace_back(row, 3 * a + 1, dy);
        trip.emplace_back(row, 3 * a + 2, cross(rbx, rby, dx, dy));
      }
    };
    add_row(rn, nx, ny);
    p.b[rn] = std::max(0.0, rng.uniform(-0.5, 0.5));  // margin s; J v added below
    if (k.has_friction()) {
      const int rt = k.tangent_row;
      add_row(rt, tx, ty);
      p.b[rt] = 0.0;
      p.normal_row[static_cast<size_t>(rt)] = rn;
      p.mu[rt] = k.mu;
      p.lo[rt] = -INFINITY;
    }
  }
  p.J.resize(n, 3 * bodies);
  p.J.setFromTriplets(trip.begin(), trip.end());
  p.J.makeCompressed();
  p.inv_mass.resize(3 * bodies);
  for (int k = 0; k < bodies; ++k) {
    const double m = M_PI * rng.uniform(0.5, 2.0);
    p.inv_mass[3 * k] = p.inv_mass[3 * k + 1] = 1.0 / m;
    p.inv_mass[3 * k + 2] = 1.0 / (0.5 * m);
  }
  p.dt = 0.01;
  Eigen::VectorXd v(3 * bodies);
  for (int k = 0; k < bodies; ++k) {
    v[3 * k] = rng.uniform(-1, 1);
    v[3 * k + 1] = rng.uniform(-2, 0.5);  // mostly falling
    v[3 * k + 2] = rng.uniform(-1, 1);
  }
  p.b += p.J * v;
  const SparseRowMatrix Minv_Jt_dt = (p.inv_mass.asDiagonal() * SparseRowMatrix(p.J.transpose())) * p.dt;
  p.A = p.J * Minv_Jt_dt;
  p.A.makeCompressed();
  return p;
}

/// Drop J and the constraints (a problem as if read from a file).
inline LcpProblem without_jacobian(LcpProblem p) {
  p.J = SparseRowMatrix();
  p.constraints.clear();
  p.inv_mass.resize(0);
  p.dt = 0.0;
  return p;
}

/// A deep pile at rest: `width` × `height` circles (r = 1, ρ = 1) in a sheared hexagonal
/// packing, each touching its right and upper-right neighbours (normals (1, 0) and
/// (½, √3/2)), the bottom row on the floor; friction μ on every contact (tangent row right
/// after its normal row). b = J v with v the free-fall velocity change −g Δt of every body:
/// the LCP of one step of a resting pile, whose solution carries each body's weight down the
/// pile — the slowly converging case of PGS (the error travels about one layer per sweep).
inline LcpProblem deep_pile(int width, int height, double mu) {
  const int bodies = width * height;
  const double m = M_PI, dt = 0.01, g = 9.81;
  LcpProblem p;
  std::vector<Eigen::Triplet<double>> trip;
  struct Row {
    int a, b;  // b = −1: floor under a
    double nx, ny;
  };
  std::vector<Row> contacts;
  for (int k = 0; k < bodies; ++k) {
    const int row = k / width, col = k % width;
    if (row == 0) contacts.push_back({k, -1, 0.0, 1.0});
    if (col + 1 < width) contacts.push_back({k, k + 1, 1.0, 0.0});
    if (k + width < bodies) contacts.push_back({k, k + width, 0.5, std::sqrt(3.0) / 2});
  }
  int n = 0;
  for (const Row& c : contacts) {
    const ContactConstraint& k = p.constraints[p.constraints.add(c.b < 0 ? -1 : c.a, c.b < 0 ? c.a : c.b, mu)];
    const double tx = -c.ny, ty = c.nx;
    auto add_row = [&](int row, double dx, double dy, double arm) {
      if (c.b < 0) {
        trip.emplace_back(row, 3 * c.a + 0, dx);
        trip.emplace_back(row, 3 * c.a + 1, dy);
        trip.emplace_back(row, 3 * c.a + 2, arm);
      } else {
        trip.emplace_back(row, 3 * c.a + 0, -dx);
        trip.emplace_back(row, 3 * c.a + 1, -dy);
        trip.emplace_back(row, 3 * c.a + 2, arm);  // r_a × t with r_a = n: 1 (0 for the normal)
        trip.emplace_back(row, 3 * c.b + 0, dx);
        trip.emplace_back(row, 3 * c.b + 1, dy);
        trip.emplace_back(row, 3 * c.b + 2, arm);  // r_b × t with r_b = −n: 1
      }
    };
    add_row(k.normal_row, c.nx, c.ny, 0.0);
    add_row(k.tangent_row, tx, ty, 1.0);
    n = std::max(n, k.tangent_row + 1);
  }
  p.J.resize(n, 3 * bodies);
  p.J.setFromTriplets(trip.begin(), trip.end());
  p.J.makeCompressed();
  p.lo = Eigen::VectorXd::Zero(n);
  p.hi = Eigen::VectorXd::Constant(n, INFINITY);
  p.mu = Eigen::VectorXd::Zero(n);
  p.normal_row.assign(static_cast<size_t>(n), -1);
  for (const ContactConstraint& k : p.constraints) {
    p.normal_row[static_cast<size_t>(k.tangent_row)] = k.normal_row;
    p.mu[k.tangent_row] = mu;
    p.lo[k.tangent_row] = -INFINITY;
  }
  p.inv_mass.resize(3 * bodies);
  for (int k = 0; k < bodies; ++k) {
    p.inv_mass[3 * k] = p.inv_mass[3 * k + 1] = 1.0 / m;
    p.inv_mass[3 * k + 2] = 1.0 / (0.5 * m);
  }
  p.dt = dt;
  Eigen::VectorXd v = Eigen::VectorXd::Zero(3 * bodies);
  for (int k = 0; k < bodies; ++k) v[3 * k + 1] = -g * dt;
  p.b = p.J * v;
  return p;
}

}  // namespace dc::test
