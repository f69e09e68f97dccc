// World::step on threads: collision (broad phase by rows of cells, narrow phase by pairs, the
// jobs' contact lists merged in key order), assembly (rows by contacts) and integration (bodies)
// run as parallel jobs when the solver has threads (LcpSolver::threads) and the pile is large
// enough, while they pay (the step's pacer, which leads the solver: LcpSolver::lead_threads). Every thread count gives the bits of one thread:
// bodies, contacts, λ and the solve's report, step after step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "dc/core/work_team.hpp"
#include "dc/engine/broad_phase.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "fixed_sweeps.hpp"

namespace dc {
namespace {

using test::fixed_sweeps;

bool same_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) == 0;
}

/// Every field of a step's public contacts, as bits: key, bodies, point, normal, gap, λ,
/// restitution memory and witness anchors (a field left stale by a reused contact shows here).
std::vector<std::uint64_t> contact_bits(const std::vector<Contact>& contacts) {
  std::vector<std::uint64_t> bits;
  const auto put = [&bits](double v) {
    std::uint64_t u = 0;
    std::memcpy(&u, &v, sizeof u);
    bits.push_back(u);
  };
  for (const Contact& c : contacts) {
    bits.push_back(c.key.packed());
    bits.push_back(static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.key.feature)));
    bits.push_back((static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.body_a)) << 32) |
                   static_cast<std::uint32_t>(c.body_b));
    for (const double v : {c.point.x, c.point.y, c.normal.x, c.normal.y, c.gap, c.lambda_n, c.lambda_t,
                           c.approach_velocity, c.anchor_a.x, c.anchor_a.y, c.anchor_b.x, c.anchor_b.y})
      put(v);
    bits.push_back(c.restitution_due ? 1u : 0u);
  }
  return bits;
}

/// Per step: the state hash, the λ and residual of the report, every field of the contacts;
/// after the last step the contacts' keys and λ.
struct Steps {
  std::vector<std::vector<std::uint64_t>> contacts;
  std::vector<std::uint64_t> hashes;
  std::vector<Eigen::VectorXd> lambdas;
  std::vector<double> residuals;
  std::vector<std::pair<ContactKey, double>> last_contacts;
};

/// The bodies of `def` after `steps` steps of pgs (a pile forms).
BodyState settled(const WorldDef& def, int steps) {
  World w(def);
  const auto pgs = make_solver("pgs");
  for (int k = 0; k < steps; ++k) w.step(*pgs, fixed_sweeps(10), World::WarmStart::PreviousLambda);
  return w.bodies();
}

/// `steps` steps from `bodies` with pgs-colored on `threads` threads (threaded solves forced:
/// min_batches_per_thread = 0).
Steps run_steps(const WorldDef& def, const BodyState& bodies, int threads, int steps) {
  PgsColoredDef d;
  d.threads = threads;
  d.min_batches_per_thread = 0;
  const auto solver = make_pgs_colored(d);
  EXPECT_EQ(threads, solver->threads());
  World w(def, bodies);
  Steps r;
  for (int k = 0; k < steps; ++k) {
    const StepReport rep = w.step(*solver, fixed_sweeps(10), World::WarmStart::PreviousLambda);
    r.hashes.push_back(state_hash(w.bodies()));
    r.lambdas.push_back(rep.solve.lambda);
    r.residuals.push_back(rep.solve.residual);
    r.contacts.push_back(contact_bits(w.contacts()));
  }
  for (const Contact& c : w.contacts()) r.last_contacts.emplace_back(c.key, c.lambda_n + c.lambda_t);
  return r;
}

void expect_same_run(const Steps& one, const Steps& other, const std::string& what) {
  ASSERT_EQ(one.hashes.size(), other.hashes.size());
  for (size_t k = 0; k < one.hashes.size(); ++k) {
    EXPECT_EQ(one.hashes[k], other.hashes[k]) << what << ", step " << k;
    EXPECT_TRUE(same_bits(one.lambdas[k], other.lambdas[k])) << what << ", step " << k;
    EXPECT_EQ(0, std::memcmp(&one.residuals[k], &other.residuals[k], sizeof(double))) << what << ", step " << k;
    EXPECT_TRUE(one.contacts[k] == other.contacts[k]) << what << ", contacts of step " << k;
  }
  EXPECT_EQ(one.last_contacts, other.last_contacts) << what;
}

/// A pile large enough for 3 threads' stages (World's kMinBodiesPerThread bodies a thread).
WorldDef pile(InternalOrder order, double restitution) {
  WorldDef def = stress::scaled_seed_pile(3200);
  def.bodies.internal_order = order;
  def.contact.restitution = restitution;
  return def;
}

TEST(WorldThreads, PileGivesTheSameBitsOnEveryThreadCount) {
  const WorldDef def = pile(InternalOrder::None, 0.0);
  const BodyState start = settled(def, 150);
  const Steps one = run_steps(def, start, 1, 12);
  ASSERT_GT(one.last_contacts.size(), 2000u);  // a pile: several jobs of pairs
  for (const int threads : {2, 3})
    expect_same_run(one, run_steps(def, start, threads, 12), std::to_string(threads) + " threads");
}

/// A solver with two threads that never paid on their own (threads() = 1, as pgs-colored's
/// before its pacer saw a threaded solve pay), serial "pgs" inside; it records how World::step
/// leads it.
class LedSolver final : public LcpSolver {
 public:
  [[nodiscard]] std::string name() const override { return "led"; }
  [[nodiscard]] int thread_capacity() const override { return 2; }
  void hold_threads(bool serial) override { held_ = serial; }
  void lead_threads(bool led) override { led_ = led; }
  [[nodiscard]] SolveResult solve(const LcpProblem& p, const Eigen::VectorXd& lambda0, const SolverOptions& o) override {
    solves.emplace_back(led_, held_);
    return pgs_->solve(p, lambda0, o);
  }
  std::vector<std::pair<bool, bool>> solves;  ///< per solve: led, held
  bool led_ = false, held_ = false;

 private:
  std::unique_ptr<LcpSolver> pgs_ = make_solver("pgs");
};

/// The step's own pacer judges whole steps: its first step runs the stages on the solver's
/// threads and leads the solver unheld, the second (the serial step it compares with) holds it,
/// and after each step the solver is released. Not gated by the solver's own pacing.
TEST(WorldThreads, PacedStepsLeadTheSolverFromTheFirstStep) {
  World w(pile(InternalOrder::None, 0.0));
  LedSolver solver;
  std::vector<TeamRunTrace> trace;
  calling_thread_team().set_trace(&trace);
  (void)w.step(solver, fixed_sweeps(5), World::WarmStart::PreviousLambda);
  const size_t first_runs = trace.size();
  (void)w.step(solver, fixed_sweeps(5), World::WarmStart::PreviousLambda);
  calling_thread_team().set_trace(nullptr);
  EXPECT_GT(first_runs, 0u);              // the first step's stages ran on the team
  EXPECT_EQ(first_runs, trace.size());    // the second step's did not
  ASSERT_EQ(2u, solver.solves.size());
  EXPECT_EQ(std::make_pair(true, false), solver.solves[0]);
  EXPECT_EQ(std::make_pair(true, true), solver.solves[1]);
  EXPECT_FALSE(solver.led_);
  EXPECT_FALSE(solver.held_);
}

/// pgs-colored keeps the pacer of the steps it leads (LcpSolver::step_pacer), so a World made
/// afresh goes on from the verdict of the steps before it: after one threaded step of a first
/// World (the pacer then wants a serial step to judge it against), a second World's first step
/// with the same solver is that serial step, not a fresh pacer's threaded first step. A solver
/// that keeps no pacer (LedSolver) leaves each World its own, whose first step is threaded.
TEST(WorldThreads, SolverKeepsTheStepPacerAcrossWorlds) {
  PgsColoredDef d;
  d.threads = 2;
  const auto solver = make_pgs_colored(d);
  ASSERT_FALSE(solver->threads_forced());
  const WorldDef def = pile(InternalOrder::None, 0.0);
  std::vector<TeamRunTrace> trace;
  calling_thread_team().set_trace(&trace);
  World first(def);
  (void)first.step(*solver, fixed_sweeps(5), World::WarmStart::PreviousLambda);
  const size_t first_runs = trace.size();
  World second(def);
  (void)second.step(*solver, fixed_sweeps(5), World::WarmStart::PreviousLambda);
  const size_t second_runs = trace.size() - first_runs;
  World own_first(def), own_second(def);
  LedSolver led;
  (void)own_first.step(led, fixed_sweeps(5), World::WarmStart::PreviousLambda);
  (void)own_second.step(led, fixed_sweeps(5), World::WarmStart::PreviousLambda);
  calling_thread_team().set_trace(nullptr);
  EXPECT_GT(first_runs, 0u);   // the first World's first step ran on the team
  EXPECT_EQ(0u, second_runs);  // the second World's first step did not: the solver's pacer went on
  ASSERT_EQ(2u, led.solves.size());  // each World's own pacer: both first steps threaded, unheld
  EXPECT_EQ(std::make_pair(true, false), led.solves[0]);
  EXPECT_EQ(std::make_pair(true, false), led.solves[1]);
}

/// A pile of 9000 bodies: the broad phase's cell fill and pair sort run as several jobs of
/// bodies (4096 bodies a job at least) and pgs-colored's layout scans as several parts.
TEST(WorldThreads, LargePileGivesTheSameBitsOnEveryThreadCount) {
  WorldDef def = stress::scaled_seed_pile(9000);
  const BodyState start = settled(def, 150);
  const Steps one = run_steps(def, start, 1, 3);
  ASSERT_GT(one.last_contacts.size(), 2048u);
  for (const int threads : {2, 3})
    expect_same_run(one, run_steps(def, start, threads, 3), std::to_string(threads) + " threads");
}

TEST(WorldThreads, InternalOrderAndRestitutionGiveTheSameBitsOnEveryThreadCount) {
  const WorldDef def = pile(InternalOrder::Morton, 0.3);
  const BodyState start = settled(def, 150);
  const Steps one = run_steps(def, start, 1, 12);
  for (const int threads : {2, 3})
    expect_same_run(one, run_steps(def, start, threads, 12), std::to_string(threads) + " threads");
}

/// The broad phase's pair tests by rows of cells: the same sorted pairs and test count on every
/// thread count, for random circles of mixed sizes.
TEST(WorldThreads, BroadPhasePairsAreTheSameOnEveryThreadCount) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(0.0, 80.0), r(0.1, 0.9);
  std::vector<Vec2> centres(6000);
  std::vector<double> reach(centres.size());
  for (size_t k = 0; k < centres.size(); ++k) {
    centres[k] = {x(rng), x(rng)};
    reach[k] = r(rng);
  }
  UniformGridBroadPhase one;
  std::vector<std::pair<int, int>> serial;
  one.find_pairs(centres, reach, serial);
  ASSERT_GT(serial.size(), 1000u);
  for (const int threads : {2, 3, 8}) {
    UniformGridBroadPhase bp;
    std::vector<std::pair<int, int>> pairs;
    bp.find_pairs(centres, reach, pairs, threads);
    EXPECT_EQ(serial, pairs) << threads << " threads";
    EXPECT_EQ(one.last_pair_tests(), bp.last_pair_tests()) << threads << " threads";
  }
}

/// Every pair of boxes [centre ± reach] that overlap (touching included), as (i < j), sorted: a
/// sweep along x, independent of the broad phase's grid.
std::vector<std::pair<int, int>> swept_pairs(const std::vector<Vec2>& centres, const std::vector<double>& reach) {
  std::vector<int> by_x(centres.size());
  for (size_t k = 0; k < by_x.size(); ++k) by_x[k] = static_cast<int>(k);
  const auto lo_x = [&](int k) { return centres[static_cast<size_t>(k)].x - reach[static_cast<size_t>(k)]; };
  std::sort(by_x.begin(), by_x.end(), [&](int a, int b) { return lo_x(a) < lo_x(b); });
  std::vector<std::pair<int, int>> pairs;
  for (size_t u = 0; u < by_x.size(); ++u) {
    const auto a = static_cast<size_t>(by_x[u]);
    for (size_t v = u + 1; v < by_x.size() && lo_x(by_x[v]) <= centres[a].x + reach[a]; ++v) {
      const auto b = static_cast<size_t>(by_x[v]);
      if (std::max(centres[a].y - reach[a], centres[b].y - reach[b]) <=
          std::min(centres[a].y + reach[a], centres[b].y + reach[b]))
        pairs.emplace_back(std::min(by_x[u], by_x[v]), std::max(by_x[u], by_x[v]));
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

/// Random circles of mixed sizes in a square of side `side`.
void random_circles(int n, double side, unsigned seed, std::vector<Vec2>& centres, std::vector<double>& reach) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(0.0, side), r(0.1, 0.9);
  centres.resize(static_cast<size_t>(n));
  reach.resize(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    centres[static_cast<size_t>(k)] = {x(rng), x(rng)};
    reach[static_cast<size_t>(k)] = r(rng);
  }
}

/// The cell fill and the pair sort by jobs of bodies (several once there are thousands of bodies
/// per thread): the pairs a sweep finds, on every thread count, from one broad phase reused
/// across thread counts and scene sizes (its buffers sized by an earlier, larger call, its sort
/// ranges from the call before).
TEST(WorldThreads, BroadPhaseJobsOfBodiesFindTheSweepsPairs) {
  UniformGridBroadPhase reused;
  for (const auto& [n, side] : {std::pair{20000, 140.0}, std::pair{9001, 90.0}}) {
    std::vector<Vec2> centres;
    std::vector<double> reach;
    random_circles(n, side, 11, centres, reach);
    const std::vector<std::pair<int, int>> expected = swept_pairs(centres, reach);
    ASSERT_GT(expected.size(), static_cast<size_t>(n));
    std::size_t tests_one = 0;
    for (const int threads : {1, 3, 3, 2, 2, 8, 8}) {  // a repeat sorts by the last sort's shares
      std::vector<std::pair<int, int>> pairs;
      reused.find_pairs(centres, reach, pairs, threads);
      EXPECT_EQ(expected, pairs) << n << " bodies, " << threads << " threads";
      if (threads == 1) tests_one = reused.last_pair_tests();
      EXPECT_EQ(tests_one, reused.last_pair_tests()) << n << " bodies, " << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace dc
