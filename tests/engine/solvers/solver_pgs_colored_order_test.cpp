// The colour order of "pgs-colored" (ordered_coloring.hpp): colouring in contact order sweeps
// every two contacts that share a dynamic body in "pgs"'s order, so while the chains fit in the
// colours its iterates are those of "pgs" bit for bit (the kernels perform pgs's operations per
// contact and manifold); the greedy colouring stays available and reaches the same fixed point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "engine/fixed_sweeps.hpp"
#include "lcp/solver_test_problems.hpp"
#include "pgs_colored_kernels.hpp"
#include "solvers/pgs_colored/coloring/ordered_coloring.hpp"

namespace dc {
namespace {

SolverOptions sweeps(int k) {
  SolverOptions o = test::fixed_sweeps(k);
  o.record_theta = false;
  return o;
}

TEST(PgsColoredOrder, ContactsSharingABodyAreColouredInContactOrder) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    test::TestRng rng(seed);
    const LcpProblem p = test::random_contact(40, 60, true, rng);
    const std::vector<std::uint8_t> dyn(static_cast<size_t>(p.J.cols() / 3), 1);
    const std::vector<int> partner(static_cast<size_t>(p.constraints.size()), -1);
    colored::OrderedColorer colorer;
    const ContactColoring& c = colorer.color(p.constraints, dyn, partner);
    ASSERT_TRUE(is_valid_coloring(p.constraints, dyn, c));
    ASSERT_LT(c.colors, ContactColoring::kMaxColors);  // no chain wrapped round
    for (int i = 0; i < p.constraints.size(); ++i)
      for (int j = i + 1; j < p.constraints.size(); ++j) {
        const ContactConstraint &a = p.constraints[i], &b = p.constraints[j];
        const bool share = (a.body_a >= 0 && (a.body_a == b.body_a || a.body_a == b.body_b)) ||
                           (a.body_b >= 0 && (a.body_b == b.body_a || a.body_b == b.body_b));
        if (share) {
          EXPECT_LT(c.color[static_cast<size_t>(i)], c.color[static_cast<size_t>(j)]) << i << ", " << j;
        }
      }
    // The same contacts again: the same colours, marked as a repeat of the same generation.
    const std::uint64_t generation = c.generation;
    const ContactColoring& again = colorer.color(p.constraints, dyn, partner);
    EXPECT_TRUE(again.repeated);
    EXPECT_EQ(again.generation, generation);
  }
}

/// The colouring rule of ordered_coloring.hpp written plainly (per body arrays, no shortcut): the
/// colours the solver's colourer must give.
std::vector<int> reference_colors(const ContactConstraints& cons, const std::vector<std::uint8_t>& dyn,
                                  const std::vector<int>& partner) {
  constexpr int K = ContactColoring::kMaxColors;
  std::vector<std::uint64_t> used(dyn.size(), 0);
  std::vector<int> last(dyn.size(), -1);
  std::vector<int> color(static_cast<size_t>(cons.size()), ContactColoring::kOverflow);
  for (int c = 0; c < cons.size(); ++c) {
    if (partner[static_cast<size_t>(c)] == -2) {
      color[static_cast<size_t>(c)] = color[static_cast<size_t>(c) - 1];
      continue;
    }
    std::vector<int> bodies;
    for (const int b : {cons[c].body_a, cons[c].body_b})
      if (b >= 0 && dyn[static_cast<size_t>(b)] != 0) bodies.push_back(b);
    int after = -1;
    std::uint64_t taken = 0;
    for (const int b : bodies) {
      after = std::max(after, last[static_cast<size_t>(b)]);
      taken |= used[static_cast<size_t>(b)];
    }
    for (int s = 0; s < K; ++s) {
      const int colour = (after + 1 + s) % K;
      if ((taken >> colour & 1u) != 0) continue;
      color[static_cast<size_t>(c)] = colour;
      for (const int b : bodies) {
        used[static_cast<size_t>(b)] |= std::uint64_t{1} << colour;
        last[static_cast<size_t>(b)] = colour;
      }
      break;
    }
  }
  return color;
}

TEST(PgsColoredOrder, ColoursFollowTheRuleWithWallsStaticBodiesManifoldsAndWrapping) {
  // Few bodies and many contacts: chains longer than the colours wrap round and some contacts
  // overflow; walls (no body a), static bodies and manifolds' second points on the way.
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed);
    const int bodies = seed <= 3 ? 40 : 6;
    const LcpProblem p = test::random_contact(bodies, seed <= 3 ? 300 : 900, true, rng);
    std::vector<std::uint8_t> dyn(static_cast<size_t>(p.J.cols() / 3), 1);
    for (size_t k = 0; k < dyn.size(); k += 5) dyn[k] = 0;  // every fifth body static
    std::vector<int> partner(static_cast<size_t>(p.constraints.size()), -1);
    for (size_t c = 7; c < partner.size(); c += 11) partner[c] = -2;
    colored::OrderedColorer colorer;
    for (int round = 0; round < 2; ++round) {  // the second call reuses the colourer's storage
      const ContactColoring& got = colorer.color(p.constraints, dyn, partner);
      const std::vector<int> want = reference_colors(p.constraints, dyn, partner);
      ASSERT_EQ(got.color, want) << "seed " << seed << ", call " << round;
      if (bodies == 6) {
        EXPECT_GT(got.overflow, 0) << "seed " << seed << ": the test covers the overflow";
      }
    }
  }
}

void expect_iterates_of_pgs(const LcpProblem& p, const char* what) {
  const Eigen::VectorXd l0 = test::mixed_sign_start(p);
  for (int k : {1, 7, 30}) {
    const SolveResult a = make_solver("pgs")->solve(p, l0, sweeps(k));
    for (const PgsColoredDef& d : test::pgs_colored_kernel_defs()) {
      const SolveResult c = make_pgs_colored(d)->solve(p, l0, sweeps(k));
      ASSERT_TRUE(c.message.empty()) << c.message;  // the colour kernels ran, not the fallback
      ASSERT_EQ(a.lambda.size(), c.lambda.size());
      for (Eigen::Index i = 0; i < a.lambda.size(); ++i)
        ASSERT_EQ(a.lambda[i], c.lambda[i]) << what << ", " << k << " sweeps, " << to_string(d.kernel) << ", row " << i;
    }
  }
}

TEST(PgsColoredOrder, IteratesAreThoseOfPgsOnAPyramidAndAPile) {
  // The box pyramid: two-point manifolds on every face, each box on two below (base 10: chains
  // of fewer than 64 contacts); the seed pile: single contacts with friction.
  expect_iterates_of_pgs(test::settled_problem(stress::box_pyramid(10), 20), "pyramid");
  expect_iterates_of_pgs(test::settled_problem(stress::scaled_seed_pile(100), 100), "pile");
}

TEST(PgsColoredOrder, GreedyColouringReachesTheFixedPointOfTheOrderedOne) {
  WorldDef def = stress::box_pyramid(8);
  def.contact.friction = 0.0;  // a convex QP: every Gauss–Seidel order converges to its solution
  const LcpProblem p = test::settled_problem(def, 30);
  PgsColoredDef greedy;
  greedy.ordered_colors = false;
  SolverOptions o = sweeps(20000);
  o.tolerance = 1e-10;
  const SolveResult a = make_pgs_colored()->solve(p, Eigen::VectorXd(), o);
  const SolveResult b = make_pgs_colored(greedy)->solve(p, Eigen::VectorXd(), o);
  EXPECT_LE(a.residual, 1e-6);
  EXPECT_LE(b.residual, 1e-6);
  const Eigen::VectorXd ua = p.inv_mass.asDiagonal() * (p.J.transpose() * a.lambda) * p.dt;
  const Eigen::VectorXd ub = p.inv_mass.asDiagonal() * (p.J.transpose() * b.lambda) * p.dt;
  EXPECT_LE((ua - ub).cwiseAbs().maxCoeff(), 1e-6);
}

}  // namespace
}  // namespace dc
