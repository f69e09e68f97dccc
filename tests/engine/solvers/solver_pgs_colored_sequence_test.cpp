// "pgs-colored" over a sequence of steps: the solver keeps its colouring and layout between
// solves (persisting contacts keep their colour; a repeated contact set keeps the whole
// layout). Over a sequence in which contacts come and go the results stay bit-equal across
// kernels, thread counts and reruns of the sequence, reach the fixed point of "pgs", and a
// solve on the kept layout equals one that lays out the same colours afresh.
#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world.hpp"
#include "pgs_colored_kernels.hpp"

namespace dc {
namespace {

SolverOptions sweeps(int k, double tol = 0.0) {
  SolverOptions o;
  o.max_sweeps = k;
  o.tolerance = tol;
  o.record_theta = false;
  return o;
}

/// The problems of `count` consecutive steps of `def` after `skip` steps of pgs.
std::vector<LcpProblem> step_problems(const WorldDef& def, int skip, int count) {
  World world(def);
  const auto pgs = make_solver("pgs");
  for (int k = 0; k < skip; ++k) world.step(*pgs, sweeps(50));
  std::vector<LcpProblem> out;
  for (int k = 0; k < count; ++k) {
    world.collide();
    out.push_back(world.assemble());
    world.step(*pgs, sweeps(50));
  }
  return out;
}

/// A falling pile of 200 circles: contacts appear and end from step to step.
std::vector<LcpProblem> pile_sequence() {
  WorldDef def = default_world_def();
  def.bodies.count = 200;
  const double side = 30.0 * std::sqrt(2.0);
  def.world.width = def.world.height = side;
  def.bodies.mean = {side / 2, side / 2};
  def.bodies.sigma = 4.65 * std::sqrt(2.0);
  return step_problems(def, 150, 12);
}

using Key = std::tuple<int, int, int>;
std::set<Key> keys_of(const LcpProblem& p) {
  std::set<Key> out;
  for (const ContactConstraint& k : p.constraints) out.insert({k.body_a, k.body_b, k.feature});
  return out;
}

void expect_bit_equal(const SolveResult& a, const SolveResult& b, const std::string& what) {
  ASSERT_EQ(a.lambda.size(), b.lambda.size()) << what;
  for (Eigen::Index i = 0; i < a.lambda.size(); ++i) ASSERT_EQ(a.lambda[i], b.lambda[i]) << what << " row " << i;
  ASSERT_EQ(a.theta, b.theta) << what;
}

std::vector<PgsColoredDef> paths() {
  std::vector<PgsColoredDef> out = test::pgs_colored_kernel_defs();
  PgsColoredDef two;
  two.threads = 2;
  two.min_batches_per_thread = 0;
  out.push_back(two);
  return out;
}

TEST(PgsColoredSequence, ContactsComeAndGo) {
  const std::vector<LcpProblem> seq = pile_sequence();
  int changed = 0;
  for (size_t k = 1; k < seq.size(); ++k) {
    const std::set<Key> a = keys_of(seq[k - 1]), b = keys_of(seq[k]);
    std::vector<Key> gone, born;
    std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(gone));
    std::set_difference(b.begin(), b.end(), a.begin(), a.end(), std::back_inserter(born));
    changed += !gone.empty() && !born.empty();
  }
  EXPECT_GE(changed, 3) << "the sequence should lose and gain contacts between steps";
}

TEST(PgsColoredSequence, KernelsThreadsAndRerunsAreBitEqualOverTheSequence) {
  const std::vector<LcpProblem> seq = pile_sequence();
  const auto reference = make_pgs_colored();
  std::vector<std::unique_ptr<LcpSolver>> others;
  for (const PgsColoredDef& d : paths()) others.push_back(make_pgs_colored(d));
  others.push_back(make_pgs_colored());  // a rerun of the sequence
  for (size_t k = 0; k < seq.size(); ++k) {
    const SolveResult r = reference->solve(seq[k], Eigen::VectorXd(), sweeps(12));
    for (size_t s = 0; s < others.size(); ++s)
      expect_bit_equal(r, others[s]->solve(seq[k], Eigen::VectorXd(), sweeps(12)),
                       "step " + std::to_string(k) + " path " + std::to_string(s));
  }
}

TEST(PgsColoredSequence, KeptColoursReachTheFixedPointOfPgs) {
  const std::vector<LcpProblem> seq = pile_sequence();
  const auto colored = make_pgs_colored();
  const auto pgs = make_solver("pgs");
  for (size_t k = 0; k < seq.size(); ++k) {
    const LcpProblem& p = seq[k];
    const SolveResult c = colored->solve(p, Eigen::VectorXd(), sweeps(20000, 1e-10));
    const SolveResult a = pgs->solve(p, Eigen::VectorXd(), sweeps(20000, 1e-10));
    EXPECT_EQ(c.status, SolveStatus::Converged) << "step " << k << ": " << c.message;
    EXPECT_LE(c.residual, 1e-6) << "step " << k;
    // λ need not be unique on a pile: the body velocities are what both must agree on.
    const Eigen::VectorXd ua = p.inv_mass.asDiagonal() * (p.J.transpose() * a.lambda) * p.dt;
    const Eigen::VectorXd uc = p.inv_mass.asDiagonal() * (p.J.transpose() * c.lambda) * p.dt;
    EXPECT_LE((ua - uc).cwiseAbs().maxCoeff(), 1e-6) << "step " << k;
  }
}

TEST(PgsColoredSequence, KeptLayoutEqualsAFreshLayoutOfTheSameColours) {
  // After steps 0..n−2, solving step n−1 and then step n−1 with new values (the same contacts:
  // the colours and the layout are kept, the batches refilled) equals solving the new values
  // right after step n−2 (the same colours, laid out afresh).
  const std::vector<LcpProblem> seq = pile_sequence();
  const size_t n = seq.size();
  LcpProblem next = seq[n - 1];
  next.J *= 1.125;
  next.b *= 0.75;
  Eigen::VectorXd l0 = Eigen::VectorXd::Constant(next.rows(), 0.25);
  for (const PgsColoredDef& d : paths()) {
    const auto kept = make_pgs_colored(d), fresh = make_pgs_colored(d);
    for (size_t k = 0; k + 1 < n; ++k) {
      (void)kept->solve(seq[k], Eigen::VectorXd(), sweeps(4));
      (void)fresh->solve(seq[k], Eigen::VectorXd(), sweeps(4));
    }
    (void)kept->solve(seq[n - 1], Eigen::VectorXd(), sweeps(4));
    expect_bit_equal(kept->solve(next, l0, sweeps(10)), fresh->solve(next, l0, sweeps(10)),
                     std::string("kernel ") + to_string(d.kernel) + " threads " + std::to_string(d.threads));
  }
}

}  // namespace
}  // namespace dc
