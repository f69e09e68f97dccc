// pgs-colored's locality order (PgsColoredDef::locality_order, setup/body_numbering.hpp): the
// bodies' Δu stored in a breadth-first numbering and each colour's contacts in its order change
// no bit of a solve (λ, θ, sweeps, residual equal with and without it, on 1, 2 and 3 threads, over
// a sequence of solves that renumbers and changes the body count), keep the overflow set in
// contact order, and do what they are for: the two threads' regions of a pile in creation order
// (bodies spread at random) share few Δu cache lines, where in body order they share many; a
// body order that is local already (Morton) is kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "engine/fixed_sweeps.hpp"
#include "pgs_colored_kernels.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "solvers/pgs_colored/setup/body_numbering.hpp"
#include "solvers/pgs_colored/sweep_team.hpp"

namespace dc {
namespace {

/// A world of `bodies` circles in a Gaussian pile (creation order: indices spread at random over
/// it), or of boxes in a shuffled grid (two-point manifolds), after `steps` steps of pgs.
World settled(int bodies, bool boxes, int steps, BodyOrder order = BodyOrder::Creation) {
  WorldDef def = default_world_def();
  const double side = 30.0 * std::sqrt(bodies / 100.0);
  def.world.width = def.world.height = side;
  if (boxes) {
    def.bodies.count = 0;
    def.world.walls = {true, true, true, false};
    const int columns = static_cast<int>(side / 1.2) - 2;
    std::vector<int> cell(static_cast<size_t>(bodies));
    std::iota(cell.begin(), cell.end(), 0);
    test::TestRng rng(5);
    for (int i = bodies - 1; i > 0; --i) std::swap(cell[static_cast<size_t>(i)], cell[static_cast<size_t>(rng.below(i + 1))]);
    for (const int c : cell) {
      BodyDef b;
      b.shape = BodyShape::Box;
      b.size = {1, 1};
      b.position = {1.5 + 1.1 * (c % columns) + 0.05 * ((c / columns) % 2), 0.5 + 1.02 * (c / columns)};
      def.body.push_back(b);
    }
  } else {
    def = stress::scaled_seed_pile(bodies);  // (micro_step's pile)
    def.bodies.order = order;
  }
  World world(def);
  const auto pgs = make_solver("pgs");
  SolverOptions o = test::fixed_sweeps(50);
  o.record_theta = false;
  for (int k = 0; k < steps; ++k) world.step(*pgs, o);
  return world;
}

LcpProblem problem_of(World& w) {
  w.collide();
  return w.assemble();
}

/// p with one body more, in no contact (a new J column block: the contacts and their colours
/// repeat, the body count changes).
LcpProblem with_body_more(LcpProblem p) {
  const Eigen::Index cols = p.J.cols();
  p.J.conservativeResize(p.J.rows(), cols + 3);
  p.inv_mass.conservativeResize(cols + 3);
  p.inv_mass.tail(3).setConstant(1.0);
  return p;
}

std::unique_ptr<LcpSolver> solver(int threads, bool locality) {
  PgsColoredDef d;
  d.threads = threads;
  d.min_batches_per_thread = 0;  // thread even small problems
  d.locality_order = locality;
  return make_pgs_colored(d);
}

/// The solvers compared: one thread, two and three with and without the locality order.
struct Solvers {
  std::vector<std::unique_ptr<LcpSolver>> all;
  std::vector<std::string> names;
  Solvers() {
    for (const auto& [t, loc] : std::vector<std::pair<int, bool>>{{1, true}, {2, true}, {2, false}, {3, true}}) {
      all.push_back(solver(t, loc));
      names.push_back(std::to_string(t) + " threads, locality " + (loc ? "on" : "off"));
    }
  }
  /// Every solver's solve of p from l0 has the bits of the first's.
  void expect_same(const LcpProblem& p, const Eigen::VectorXd& l0, int sweeps, const std::string& what) {
    const SolveResult one = all[0]->solve(p, l0, test::fixed_sweeps(sweeps));
    ASSERT_EQ(one.status, SolveStatus::SweepLimit) << what << ": " << one.message;
    for (size_t i = 1; i < all.size(); ++i)
      test::expect_same_bits(one, all[i]->solve(p, l0, test::fixed_sweeps(sweeps)), what + ", " + names[i]);
  }
};

/// The layout of p (2 threads) with or without the locality order.
colored::Prepared laid_out(const LcpProblem& p, bool locality) {
  ContactColorer colorer(true, 0);
  colored::OrderedColorer ordered;
  colored::Prepared prep;
  EXPECT_EQ(colored::layout(p, colorer, &ordered, 2, prep, nullptr, locality), "");
  return prep;
}

bool has_serial_range(const colored::Prepared& prep) {
  return std::any_of(prep.ranges.begin(), prep.ranges.end(), [](const colored::Range& r) { return r.serial; });
}

TEST(PgsColoredLocality, SolvesHaveTheSameBitsWithAndWithoutIt) {
  Solvers s;
  test::TestRng rng(3);
  // Random problems: few bodies with many contacts (over 64 colours: an overflow set, swept in
  // contact order), walls, contacts without friction.
  for (const auto& [bodies, contacts] : std::vector<std::pair<int, int>>{{12, 500}, {80, 300}}) {
    const LcpProblem p = test::random_contact(bodies, contacts, true, rng, 0.5, 4);
    if (contacts == 500) {
      ASSERT_TRUE(has_serial_range(laid_out(p, true))) << "the test wants an overflow set";
    }
    Eigen::VectorXd l0(p.rows());
    for (int i = 0; i < p.rows(); ++i) l0[i] = rng.uniform(-1, 3);
    s.expect_same(p, l0, 6, "random " + std::to_string(bodies) + " bodies");
  }
  // A pile of circles and a grid of boxes (two-point manifolds), stepped on: a sequence of solves
  // that renumbers (BodyNumbering::kRenumberEvery) and, with the boxes, changes the body count.
  World pile = settled(600, false, 120), boxes = settled(150, true, 40);
  ASSERT_FALSE(laid_out(problem_of(boxes), true).pairs.empty()) << "the test wants manifolds";
  const auto pgs = make_solver("pgs");
  for (int step = 0; step < colored::BodyNumbering::kRenumberEvery + 3; ++step) {
    for (World* w : {&pile, &boxes}) {
      const LcpProblem p = problem_of(*w);
      const std::string what = "step " + std::to_string(step);
      s.expect_same(p, Eigen::VectorXd::Zero(p.rows()), 8, what);
      if (step % 8 == 5) s.expect_same(with_body_more(p), Eigen::VectorXd::Zero(p.rows()), 8, what + ", body more");
      w->step(*pgs, test::fixed_sweeps(30));
    }
  }
}

/// The Δu cache lines (two bodies per 64 bytes) that both threads' blocks touch in the sweeps, as
/// a fraction of those either touches.
double shared_lines(const colored::Prepared& prep) {
  std::vector<int> keys, cuts;
  colored::region_cuts(prep, 2, keys, cuts);
  std::set<int> lines[2];
  auto touch = [&](int t, const auto& batch) {
    for (int lane = 0; lane < batch.count; ++lane)
      for (const int at : {batch.la[lane], batch.lb[lane]})
        if (at < prep.body_entries) lines[t].insert(at / 8);
  };
  for (size_t k = 0; k < prep.ranges.size(); ++k) {
    const colored::Range& rg = prep.ranges[k];
    if (rg.serial) continue;
    for (int i = rg.begin; i < rg.end; ++i) {
      const int t = i < cuts[k] ? 0 : 1;
      if (rg.pairs)
        touch(t, prep.pairs[static_cast<size_t>(i)]);
      else
        touch(t, prep.batches[static_cast<size_t>(i)]);
    }
  }
  int both = 0;
  for (const int l : lines[0]) both += lines[1].count(l) > 0 ? 1 : 0;
  std::set<int> either = lines[0];
  either.insert(lines[1].begin(), lines[1].end());
  return static_cast<double>(both) / static_cast<double>(either.size());
}

TEST(PgsColoredLocality, ThreadsShareFewDeltaULinesOnAPileInCreationOrder) {
  World pile = settled(2000, false, 150);
  const LcpProblem p = problem_of(pile);
  colored::Prepared with = laid_out(p, true), without = laid_out(p, false);
  // Fill the batches (their la/lb are the Δu offsets).
  for (colored::Prepared* prep : {&with, &without}) {
    std::vector<double> lp(prep->row_of.size()), other(prep->row_of.size());
    const Eigen::VectorXd l0 = Eigen::VectorXd::Zero(p.rows());
    for (int bi = 0; bi < static_cast<int>(prep->batches.size()); ++bi)
      colored::fill_batch(p, l0, *prep, bi, lp.data(), other.data());
  }
  std::vector<int> slot = with.numbering.slot;
  std::sort(slot.begin(), slot.end());
  for (int k = 0; k < static_cast<int>(slot.size()); ++k) ASSERT_EQ(slot[static_cast<size_t>(k)], k) << "a permutation";
  const double on = shared_lines(with), off = shared_lines(without);
  EXPECT_LT(3.0 * on, off) << "shared Δu lines: " << on << " with the locality order, " << off << " without";
}

TEST(PgsColoredLocality, ABodyOrderThatIsLocalAlreadyIsKept) {
  // Bodies numbered in space (Morton order): a cut in body index is as short as one in the
  // breadth-first numbers, so the layout keeps slot = body and contact order (no key sort).
  World morton = settled(2000, false, 150, BodyOrder::Morton), creation = settled(2000, false, 150);
  const colored::Prepared kept = laid_out(problem_of(morton), true);
  EXPECT_TRUE(kept.numbering.local_already);
  for (int k = 0; k < static_cast<int>(kept.numbering.slot.size()); ++k)
    ASSERT_EQ(kept.numbering.slot[static_cast<size_t>(k)], k);
  EXPECT_FALSE(laid_out(problem_of(creation), true).numbering.local_already);
}

TEST(PgsColoredLocality, BreadthFirstNumbersAChainFromAnEnd) {
  // A chain of 9 dynamic bodies in shuffled index order, hung on a static body (index 9) and a
  // wall contact: the numbers run along the chain from one end, the static body comes last.
  const std::vector<int> chain = {4, 7, 1, 8, 0, 3, 6, 2, 5};
  ContactConstraints cons;
  cons.add(-1, chain[3], 0.5);
  for (size_t i = 0; i + 1 < chain.size(); ++i) cons.add(chain[i], chain[i + 1], 0.5);
  cons.add(9, chain[6], 0.5);
  std::vector<std::uint8_t> dynamic(10, 1);
  dynamic[9] = 0;
  colored::BodyNumbering n;
  colored::number_bodies(cons, dynamic, 10, n);
  const int first = n.slot[static_cast<size_t>(chain[0])];
  ASSERT_TRUE(first == 0 || first == 8) << first;
  for (size_t i = 0; i < chain.size(); ++i)
    EXPECT_EQ(n.slot[static_cast<size_t>(chain[i])], first == 0 ? static_cast<int>(i) : 8 - static_cast<int>(i));
  EXPECT_EQ(n.slot[9], 9);
  // The contacts by key (their lower dynamic slot), stable: contact order among equal keys.
  colored::order_by_key(cons, dynamic, 10, n);
  for (size_t q = 0; q + 1 < n.order.size(); ++q) {
    const int a = n.order[q], b = n.order[q + 1];
    EXPECT_TRUE(n.key[static_cast<size_t>(a)] < n.key[static_cast<size_t>(b)] ||
                (n.key[static_cast<size_t>(a)] == n.key[static_cast<size_t>(b)] && a < b));
  }
}

TEST(PgsColoredLocality, KeyOrderIsTheSameOnOneTwoAndThreeThreads) {
  // Enough contacts for blocks on every thread (a few thousand each), keys with many repeats
  // (few bodies) and bodies that are static: the stable key order on every thread count.
  test::TestRng rng(29);
  const LcpProblem p = test::random_contact(1500, 20000, true, rng, 0.5, 3);
  const int bodies = static_cast<int>(p.J.cols() / 3);
  std::vector<std::uint8_t> dynamic(static_cast<size_t>(bodies), 1);
  for (int k = 0; k < bodies; k += 7) dynamic[static_cast<size_t>(k)] = 0;
  colored::BodyNumbering one;
  colored::number_bodies(p.constraints, dynamic, bodies, one);
  colored::order_by_key(p.constraints, dynamic, bodies, one, 1);
  for (size_t q = 0; q + 1 < one.order.size(); ++q) {
    const int a = one.order[q], b = one.order[q + 1];
    ASSERT_TRUE(one.key[static_cast<size_t>(a)] < one.key[static_cast<size_t>(b)] ||
                (one.key[static_cast<size_t>(a)] == one.key[static_cast<size_t>(b)] && a < b))
        << "position " << q;
  }
  for (const int threads : {2, 3}) {
    colored::BodyNumbering n = one;
    std::fill(n.order.begin(), n.order.end(), -1);
    std::fill(n.key.begin(), n.key.end(), -1);
    colored::order_by_key(p.constraints, dynamic, bodies, n, threads);
    EXPECT_EQ(n.key, one.key) << threads << " threads";
    EXPECT_EQ(n.order, one.order) << threads << " threads";
  }
}

/// A serial layout (no locality: a serial step between threaded ones) sweeps with slot = body,
/// which keeps the Δu reads of contact order in body order, and sets the locality numbering
/// aside: the next locality layout takes it back instead of numbering the bodies again.
TEST(PgsColoredLocality, ASerialLayoutUsesBodyOrderAndKeepsTheNumberingForTheNext) {
  World pile = settled(2000, false, 150);
  const LcpProblem p = problem_of(pile);
  colored::Prepared prep;
  auto lay_out_again = [&](bool locality) {  // a fresh colourer: a fresh layout, never the last one reused
    ContactColorer colorer(true, 0);
    colored::OrderedColorer ordered;
    EXPECT_EQ(colored::layout(p, colorer, &ordered, 2, prep, nullptr, locality), "");
  };
  lay_out_again(true);
  const std::vector<int> local = prep.numbering.slot;
  ASSERT_FALSE(prep.numbering.local_already);
  lay_out_again(false);
  for (int k = 0; k < static_cast<int>(prep.numbering.slot.size()); ++k)
    ASSERT_EQ(prep.numbering.slot[static_cast<size_t>(k)], k) << "the serial layout: slot = body";
  lay_out_again(true);
  EXPECT_EQ(local, prep.numbering.slot);  // taken back
  EXPECT_EQ(1, prep.numbering.age);       // one layout older, not numbered again (age 0)
}

}  // namespace
}  // namespace dc
