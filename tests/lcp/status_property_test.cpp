// The status property: no solver calls a λ `converged` that is not a solution. Every solver of
// solver_names() and the proximal route runs on random small problems of six classes and every
// `Converged` is checked here, independently of the library's decide_status, against the
// solution test of docs/lcp.md "Statuses":
//     natural_residual(p, λ) ≤ exact_tolerance · max(‖b‖∞, DBL_MIN)
// with the residual recomputed from the returned λ. The classes are the ones where a stopping
// rule can pass on a non-solution: symmetric PSD singular W, non-symmetric W (P-matrix and
// not), whole problems scaled by 1e±12, degenerate problems (zeros in b, duplicated rows) and
// frictional contact problems (box friction ±μλ_n, with J, so pgs, pgs-colored and nncg run
// their matrix-free form). The tolerance mode varies (θ from 1e-4 to 1e-12, and fixed sweeps)
// so that θ-stops happen both on and off a solution. The counts (converged, tolerance_reached,
// other) per class are printed and recorded as test properties.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "dc/lcp/proximal_point.hpp"
#include "solver_test_problems.hpp"

namespace dc {
namespace {

using test::TestRng;

constexpr int kPerClass = 1700;  // × 6 classes ≥ 10,000 problems per solver
constexpr double kExactTolerance = 1e-9;

enum Class { PsdSingular, NonSymmetricP, NonSymmetric, BadlyScaled, Degenerate, Frictional, kClasses };
constexpr std::array<const char*, kClasses> kClassNames = {"psd_singular", "nonsym_p",   "nonsym",
                                                           "scaled_1e12",  "degenerate", "frictional"};

Eigen::MatrixXd random_matrix(int rows, int cols, TestRng& rng) {
  Eigen::MatrixXd m(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) m(i, j) = rng.uniform(-1, 1);
  return m;
}

Eigen::VectorXd random_vector(int n, TestRng& rng) {
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = rng.uniform(-1, 1);
  return v;
}

/// A = B Bᵀ with B of rank < n, symmetrised bit for bit.
Eigen::MatrixXd psd_singular(int n, TestRng& rng) {
  const Eigen::MatrixXd B = random_matrix(n, 1 + rng.below(n - 1), rng);
  const Eigen::MatrixXd A = B * B.transpose();
  return 0.5 * (A + A.transpose());
}

/// b: half random, half b = −A x + s with x ≥ 0 and s ≥ 0 complementary (solvable).
Eigen::VectorXd rhs(const Eigen::MatrixXd& A, TestRng& rng) {
  const int n = static_cast<int>(A.rows());
  if (rng.below(2) == 0) return random_vector(n, rng);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n), s = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i) (rng.below(2) ? x[i] : s[i]) = rng.uniform(0, 1);
  return s - A * x;
}

LcpProblem make_problem(Class c, TestRng& rng) {
  const int n = 2 + rng.below(5);  // 2..6 rows
  switch (c) {
    case PsdSingular: {
      const Eigen::MatrixXd A = psd_singular(n, rng);
      return LcpProblem::standard(A, rhs(A, rng));
    }
    case NonSymmetricP: {  // strictly diagonally dominant rows, positive diagonal: a P-matrix
      Eigen::MatrixXd A = random_matrix(n, n, rng);
      for (int i = 0; i < n; ++i) A(i, i) = A.row(i).cwiseAbs().sum() + rng.uniform(0.01, 1);
      return LcpProblem::standard(A, random_vector(n, rng));
    }
    case NonSymmetric: {  // anything: indefinite, zero or negative diagonals, often unsolvable
      const Eigen::MatrixXd A = random_matrix(n, n, rng);
      return LcpProblem::standard(A, rhs(A, rng));
    }
    case BadlyScaled: {  // A and b scaled apart by up to 1e±12
      const double scales[] = {1e-12, 1.0, 1e12};
      const double sa = scales[rng.below(3)], sb = scales[rng.below(3)];
      Eigen::MatrixXd A = rng.below(2) ? psd_singular(n, rng) : test::random_spd(n, rng).A.toDense();
      const Eigen::VectorXd b = rhs(A, rng);
      return LcpProblem::standard(Eigen::MatrixXd(sa * A), sb * b);
    }
    case Degenerate: {  // zeros in b and a duplicated row/column
      Eigen::MatrixXd A0 = test::random_spd(n, rng).A.toDense();
      Eigen::VectorXd b0 = rhs(A0, rng);
      for (int i = 0; i < n; ++i)
        if (rng.below(3) == 0) b0[i] = 0.0;
      const int d = rng.below(n);
      Eigen::MatrixXd A(n + 1, n + 1);
      Eigen::VectorXd b(n + 1);
      auto src = [&](int i) { return i < n ? i : d; };
      for (int i = 0; i <= n; ++i) {
        b[i] = b0[src(i)];
        for (int j = 0; j <= n; ++j) A(i, j) = A0(src(i), src(j));
      }
      return LcpProblem::standard(A, b);
    }
    case Frictional:
    default: {
      LcpProblem p = test::random_contact(2 + rng.below(2), 1 + rng.below(3), true, rng, rng.uniform(0.1, 1.0));
      if (rng.below(4) == 0) p.b *= 1e-6;  // a slow contact: small b, same A
      return p;
    }
  }
}

/// Per class: solves, Converged (checked), ToleranceReached, anything else.
struct Counts {
  int total = 0, converged = 0, tolerance_reached = 0, other = 0, false_claims = 0;
};

SolveResult run(const std::string& solver, const LcpProblem& p, const SolverOptions& o) {
  if (solver == "proximal") {
    ProximalPointDef def;
    def.max_outer = 6;  // the route's claim is what is tested, not its patience
    def.inner_iterations = 50;
    SolverOptions po = o;
    po.tolerance = 0.0;  // `lcp solve --proximal` runs it to the solution test
    return solve_proximal_point(p, Eigen::VectorXd(), po, def);
  }
  if (solver == "prox-newton") {
    ProxNewtonDef def;  // every stage runs; the claim is what is tested, not the patience
    def.max_outer = 6;
    def.finish_route.max_outer = 6;
    def.finish_route.inner_iterations = 50;
    def.dual_finish_route.max_outer = 6;
    def.dual_finish_route.inner_iterations = 50;
    def.safeguard_sweeps = 300;
    return make_prox_newton(def)->solve(p, Eigen::VectorXd(), o);
  }
  return make_solver(solver)->solve(p, Eigen::VectorXd(), o);
}

class StatusProperty : public testing::TestWithParam<std::string> {};

TEST_P(StatusProperty, NoConvergedWithoutASolution) {
  const std::string solver = GetParam();
  std::array<Counts, kClasses> counts{};
  uint64_t seed = 0x57a7e5ull;  // FNV-1a of the name: one stream per solver
  for (char ch : solver) seed = (seed ^ static_cast<unsigned char>(ch)) * 0x100000001b3ull;
  TestRng rng(seed);
  const double tolerances[] = {0.0, 1e-4, 1e-8, 1e-12};
  for (int c = 0; c < kClasses; ++c) {
    for (int k = 0; k < kPerClass; ++k) {
      const LcpProblem p = make_problem(static_cast<Class>(c), rng);
      SolverOptions o;
      o.max_sweeps = 300;
      o.record_theta = false;
      o.exact_tolerance = kExactTolerance;
      o.tolerance = tolerances[rng.below(4)];
      if (solver == "psor") o.omega = 1.3;
      if (solver == "jacobi") o.omega = 0.4;
      const SolveResult r = run(solver, p, o);
      Counts& n = counts[static_cast<size_t>(c)];
      ++n.total;
      if (r.status == SolveStatus::ToleranceReached) ++n.tolerance_reached;
      if (r.status != SolveStatus::Converged) {
        if (r.status != SolveStatus::ToleranceReached) ++n.other;
        continue;
      }
      ++n.converged;
      ASSERT_EQ(r.lambda.size(), p.rows());
      const double residual = natural_residual(p, r.lambda);
      const double target = kExactTolerance * std::max(p.b.lpNorm<Eigen::Infinity>(), std::numeric_limits<double>::min());
      if (!(residual <= target)) {
        if (++n.false_claims <= 3)
          ADD_FAILURE() << solver << " on a " << kClassNames[static_cast<size_t>(c)] << " problem (" << p.rows()
                        << " rows, tolerance " << o.tolerance << "): converged with natural residual " << residual
                        << " > target " << target << " (" << r.message << ")";
      }
    }
  }
  int total = 0, converged = 0;
  std::string summary = solver + ":";
  for (int c = 0; c < kClasses; ++c) {
    const Counts& n = counts[static_cast<size_t>(c)];
    const std::string name = kClassNames[static_cast<size_t>(c)];
    RecordProperty(name + "_total", n.total);
    RecordProperty(name + "_converged", n.converged);
    RecordProperty(name + "_tolerance_reached", n.tolerance_reached);
    RecordProperty(name + "_other", n.other);
    char buf[160];
    std::snprintf(buf, sizeof buf, " %s %d/%d/%d/%d", name.c_str(), n.total, n.converged, n.tolerance_reached,
                  n.other);
    summary += buf;
    total += n.total;
    converged += n.converged;
    EXPECT_EQ(n.false_claims, 0) << solver << ", " << name << ": converged above the solution test";
  }
  std::printf("status property (class total/converged/tolerance_reached/other) %s\n", summary.c_str());
  EXPECT_GE(total, 10000);
  EXPECT_GT(converged, 0) << solver << " never converged: the test would check nothing";
}

// A problem scaled by 1e12 (A ≈ 1e12, b ≈ 1, λ ≈ 1e-12): one sweep moves λ by less than any
// absolute θ tolerance, so the sweep solvers stop after it — at a λ that is not a solution.
TEST(StatusProperty, ThetaStopOnABadlyScaledProblemIsNoSolutionClaim) {
  TestRng rng(12);
  const LcpProblem base = test::random_spd(4, rng);
  const LcpProblem p = LcpProblem::standard(Eigen::MatrixXd(1e12 * base.A.toDense()), -Eigen::VectorXd::Ones(4));
  SolverOptions o;
  o.tolerance = 1e-6;
  for (const char* name : {"pgs", "pgs-assembled", "nncg", "psor"}) {
    const SolveResult r = make_solver(name)->solve(p, Eigen::VectorXd(), o);
    if (r.status == SolveStatus::Converged)
      EXPECT_LE(natural_residual(p, r.lambda), 1e-9) << name;
    else
      EXPECT_EQ(r.status, SolveStatus::ToleranceReached) << name << ": " << to_string(r.status);
  }
  const SolveResult exact = make_solver("newton")->solve(p, Eigen::VectorXd(), o);
  EXPECT_EQ(exact.status, SolveStatus::Converged) << exact.message;
}

// The proximal route around a solver that refuses the problem reports the refusal.
TEST(StatusProperty, ProximalRouteReportsItsInnerSolversRefusal) {
  TestRng rng(3);
  const LcpProblem p = test::random_contact(3, 3, true, rng);
  ProximalPointDef def;
  def.inner_solver = SolverId{SolverKind::Lemke, 0, std::nullopt};
  const SolveResult r = solve_proximal_point(p, Eigen::VectorXd(), SolverOptions{}, def);
  EXPECT_EQ(r.status, SolveStatus::InvalidInput) << r.message;
  EXPECT_NE(r.message.find("lemke"), std::string::npos) << r.message;
}

std::vector<std::string> all_solvers() {
  std::vector<std::string> s = solver_names();
  s.push_back("proximal");
  return s;
}

INSTANTIATE_TEST_SUITE_P(EverySolver, StatusProperty, testing::ValuesIn(all_solvers()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           std::string n = info.param;
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });

}  // namespace
}  // namespace dc
