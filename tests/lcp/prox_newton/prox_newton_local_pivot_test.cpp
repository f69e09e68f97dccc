// prox-newton's local pivoting finish (pivot_finish.hpp: local_pivot_rows, local_pivot_solve):
// from an iterate that is exact except on a few contacts with the wrong modes, Lemke on those
// contacts with the rest fixed reaches the hard target; the solver reaches it through that
// finish when every other part is cut short, bit-equal on a rerun.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <optional>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/prox_newton/pivot_finish.hpp"

namespace dc {
namespace {

using solvers::prox::local_pivot_rows;
using solvers::prox::local_pivot_solve;
using solvers::prox::pivot_solve;

struct Case {
  LcpProblem p;
  Eigen::VectorXd exact;  // Lemke on the whole problem
  Eigen::VectorXd wrong;  // exact, with closed contacts opened (λ_n = 0, λ_t = 0)
  std::vector<int> opened;
};

/// A contact problem, its exact solution, and that solution with `k` closed contacts opened:
/// an active set that is wrong on a few contacts only (closed contacts read as open).
std::optional<Case> make_case(uint64_t seed, int k) {
  test::TestRng rng(seed);
  Case c;
  c.p = test::without_jacobian(test::random_contact(12, 30, true, rng));
  const solvers::prox::PivotOutcome po = pivot_solve(c.p);
  if (!po.lambda) return std::nullopt;
  c.exact = *po.lambda;
  c.wrong = c.exact;
  for (int i = 0; i < c.p.rows() && static_cast<int>(c.opened.size()) < k; ++i) {
    if (c.p.is_friction_row(i) || !(c.exact[i] > 1e-3 * c.exact.cwiseAbs().maxCoeff())) continue;
    c.opened.push_back(i);
    for (int j = 0; j < c.p.rows(); ++j)
      if (j == i || c.p.normal_row[static_cast<size_t>(j)] == i) c.wrong[j] = 0.0;
  }
  if (static_cast<int>(c.opened.size()) < k) return std::nullopt;
  return c;
}

double scale(const LcpProblem& p) { return std::max(1.0, p.b.lpNorm<Eigen::Infinity>()); }

TEST(ProxNewtonLocalPivot, FixesTheWrongContactsWithTheRestFixed) {
  int cases = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    const auto c = make_case(seed + 1200, 2);
    if (!c) continue;
    ++cases;
    const double before = natural_residual(c->p, c->wrong);
    ASSERT_GT(before, 1e-6 * scale(c->p)) << "seed " << seed << ": opening the contacts left them right";
    const std::vector<int> rows = local_pivot_rows(c->p, c->wrong, 1e-9 * before, 0, 1 << 20);
    ASSERT_FALSE(rows.empty());
    ASSERT_LT(static_cast<int>(rows.size()), c->p.rows()) << "seed " << seed << ": not a local subproblem";
    for (const int i : c->opened) EXPECT_TRUE(std::binary_search(rows.begin(), rows.end(), i)) << "row " << i;
    const solvers::prox::PivotOutcome po = local_pivot_solve(c->p, c->wrong, rows, 0.0);
    ASSERT_TRUE(po.lambda.has_value()) << po.why;
    EXPECT_LE(natural_residual(c->p, *po.lambda), 1e-8 * scale(c->p)) << "seed " << seed;
    // Rows outside the subproblem keep their values.
    for (int i = 0; i < c->p.rows(); ++i) {
      if (!std::binary_search(rows.begin(), rows.end(), i)) {
        EXPECT_EQ((*po.lambda)[i], c->wrong[i]);
      }
    }
  }
  EXPECT_GE(cases, 3);
}

TEST(ProxNewtonLocalPivot, RingsAddCoupledContactsWithinTheSize) {
  const auto c = make_case(1201, 1);
  ASSERT_TRUE(c.has_value());
  const double thr = 1e-9 * natural_residual(c->p, c->wrong);
  const std::vector<int> none = local_pivot_rows(c->p, c->wrong, thr, 0, 1 << 20);
  const std::vector<int> one = local_pivot_rows(c->p, c->wrong, thr, 1, 1 << 20);
  EXPECT_GT(one.size(), none.size());
  EXPECT_TRUE(std::includes(one.begin(), one.end(), none.begin(), none.end()));
  // The violators alone exceed a size of 1: nothing.
  EXPECT_TRUE(local_pivot_rows(c->p, c->wrong, thr, 1, 1).empty());
  // At the exact solution there is no violator.
  EXPECT_TRUE(local_pivot_rows(c->p, c->exact, 1e-6 * scale(c->p), 2, 1 << 20).empty());
}

// Every part but the local finish cut short, started from the iterate with wrong contacts: the
// local finish reaches the target and the message names the pivoting finish; without it the
// same solve does not converge. Reruns are bit-equal.
TEST(ProxNewtonLocalPivot, SolverReachesTheTargetThroughTheLocalFinish) {
  ProxNewtonDef d;
  d.lead_sweeps = 0;
  d.max_outer = 1;
  d.inner_iterations = 1;
  d.finish_iterations = 0;
  d.proximal_finish = false;
  d.body_finish = false;
  d.safeguard_sweeps = 0;
  d.pivot_rows = 0;
  d.local_pivot_rows = 600;
  d.local_pivot_threshold = 1e-3;
  ProxNewtonDef without = d;
  without.local_pivot_rows = 0;
  SolverOptions o;
  o.max_sweeps = 1;
  int cases = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    const auto c = make_case(seed + 1200, 2);
    if (!c) continue;
    const SolveResult cut = ProxNewtonSolver(without).solve(c->p, c->wrong, o);
    if (cut.status == SolveStatus::Converged) continue;
    ++cases;
    const SolveResult r = ProxNewtonSolver(d).solve(c->p, c->wrong, o);
    EXPECT_EQ(r.status, SolveStatus::Converged) << "seed " << seed << ": " << r.message;
    EXPECT_NE(r.message.find("lemke pivoting finish"), std::string::npos) << r.message;
    const SolveResult again = ProxNewtonSolver(d).solve(c->p, c->wrong, o);
    EXPECT_TRUE(again.lambda == r.lambda) << "seed " << seed << ": rerun differs";
  }
  EXPECT_GE(cases, 2);
}

TEST(ProxNewtonLocalPivot, RejectsBadOptions) {
  ProxNewtonDef d;
  d.local_pivot_threshold = 0;
  EXPECT_THROW(ProxNewtonSolver{d}, InvalidArgument);
  d = {};
  d.local_pivot_rings = -1;
  EXPECT_THROW(ProxNewtonSolver{d}, InvalidArgument);
}

}  // namespace
}  // namespace dc
