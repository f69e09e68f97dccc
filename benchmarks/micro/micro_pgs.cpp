// Google Benchmark of the PGS sweep, matrix-free ("pgs") and assembled ("pgs-assembled"), on
// a hexagonal pile of N circles (r = 1, ρ = 1, ≈ 2 contacts per body plus floor contacts,
// friction on, Δt = 0.01), rows in body order (argument 0) or interleaved (1). One iteration
// is one solve of S sweeps (tolerance 0); counter ns_per_row_sweep = CPU time / (rows · sweeps)
// [ns]. BM_PgsBaseline is a benchmark-only row-by-row kernel timed in the same process as the
// reference; every benchmark reports max_diff_vs_baseline (0: bit-identical iterates).
// BM_SeedScene*, BM_PgsColored* (AVX-512 / AVX2 / scalar kernels, 1 or 2 threads,
// max_diff_vs_scalar), BM_ContactColoring*: docs/bench.md "Micro benchmarks". The table of
// docs/solvers.md is one run of
//   build/bin/micro_pgs --benchmark_filter='200/0|SeedScene|Coloring' --benchmark_min_time=0.2
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <cstring>
#include <ctime>
#include <utility>
#include <vector>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "dc/engine/world.hpp"
#include "hex_pile.hpp"
#include "solvers/pgs_colored/coloring/contact_coloring.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_products.hpp"
#include "solvers/pgs_colored/pgs_colored_residual.hpp"

namespace {

/// The hex pile (hex_pile.hpp) with A formed; order 0: rows in body order (the engine's
/// order), 1: interleaved.
dc::LcpProblem pile(int bodies, int order) {
  dc::LcpProblem p = dc::bench_fixture::hex_pile(
      bodies, order == 1 ? dc::bench_fixture::HexPileOrder::Interleaved : dc::bench_fixture::HexPileOrder::Bodies);
  const dc::SparseRowMatrix Minv_Jt = (p.inv_mass.asDiagonal() * dc::SparseRowMatrix(p.J.transpose())) * p.dt;
  p.A = p.J * Minv_Jt;
  p.A.makeCompressed();
  return p;
}

// ---- baseline: a row-by-row matrix-free kernel ------------------------------------------
// A benchmark-only row-by-row sweep (one packed 152-byte row per LCP row, the tangent row
// reading λ_n and Δu back from memory, wall rows writing a shared dummy body), timed in the
// same process under the same load as the contact-block kernels. Fixed sweeps only; it keeps
// the per-sweep costs of the real driver (the copy of λ for the last finite iterate, allFinite
// over Δu) so that the comparison is fair.
namespace baseline {

struct PackedRow {
  std::array<double, 6> j, mj;
  double b;
  bool singular;
  double lo_fixed, hi_fixed, mu;
  int a, bb, coupled;
};

Eigen::VectorXd solve(const dc::LcpProblem& p, int sweeps) {
  const int n = p.rows();
  const int dummy = static_cast<int>(p.J.cols());
  std::vector<PackedRow> rows(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    PackedRow& r = rows[static_cast<size_t>(i)];
    r.j.fill(0.0);
    r.mj.fill(0.0);
    r.a = r.bb = -1;
    for (dc::SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) {
      const int col = static_cast<int>(it.col()), off = 3 * (col / 3);
      int slot;
      if (r.a < 0 || r.a == off) {
        r.a = off;
        slot = col % 3;
      } else {
        r.bb = off;
        slot = 3 + col % 3;
      }
      r.j[static_cast<size_t>(slot)] += it.value();
    }
    double diag = 0.0;
    for (int s = 0; s < 6; ++s) {
      const int off = s < 3 ? r.a : r.bb;
      if (off < 0) continue;
      r.mj[static_cast<size_t>(s)] = r.j[static_cast<size_t>(s)] * p.inv_mass[off + s % 3] * p.dt;
      diag += r.j[static_cast<size_t>(s)] * r.mj[static_cast<size_t>(s)];
    }
    if (r.a < 0) r.a = dummy;
    if (r.bb < 0) r.bb = dummy;
    const double inv = 1.0 / diag;
    r.singular = !(diag > 0 && std::isfinite(inv));
    const double scale = r.singular ? 1.0 : inv;
    for (double& v : r.j) v *= scale;
    r.b = p.b[i] * scale;
    const bool fr = p.is_friction_row(i);
    r.lo_fixed = fr ? 0.0 : p.lo[i];
    r.hi_fixed = fr ? 0.0 : p.hi[i];
    r.mu = fr ? p.mu[i] : 0.0;
    r.coupled = fr ? p.normal_row[static_cast<size_t>(i)] : i;
  }
  std::vector<double> du(static_cast<size_t>(dummy + 3), 0.0);
  Eigen::VectorXd l = Eigen::VectorXd::Zero(n), last;
  for (int k = 0; k < sweeps; ++k) {
    last = l;
    double* __restrict lam = l.data();
    double* __restrict u = du.data();
    const PackedRow* __restrict row = rows.data();
    double theta = 0.0;
    bool bad = false;
    for (int i = 0; i < n; ++i, ++row) {
      double* ua = u + row->a;
      double* ub = u + row->bb;
      const double s0 = std::fma(row->j[0], ua[0], row->j[1] * ua[1]);
      const double s1 = std::fma(row->j[2], ua[2], row->j[3] * ub[0]);
      const double s2 = std::fma(row->j[4], ub[1], row->j[5] * ub[2]);
      const double res = (row->b + s0) + (s1 + s2);
      const double old = lam[i];
      const double t = row->mu * std::max(0.0, lam[row->coupled]);
      const double lo = row->lo_fixed - t, hi = row->hi_fixed + t;
      double x = old - res;  // (the singular branch is never taken on these problems)
      x = std::min(std::max(x, lo), hi);
      const double d = x - old;
      bad |= !std::isfinite(x);
      lam[i] = x;
      ua[0] = std::fma(row->mj[0], d, ua[0]);
      ua[1] = std::fma(row->mj[1], d, ua[1]);
      ua[2] = std::fma(row->mj[2], d, ua[2]);
      ub[0] = std::fma(row->mj[3], d, ub[0]);
      ub[1] = std::fma(row->mj[4], d, ub[1]);
      ub[2] = std::fma(row->mj[5], d, ub[2]);
      theta = std::max(theta, std::abs(d));
    }
    u[dummy] = u[dummy + 1] = u[dummy + 2] = 0.0;
    if (bad || !std::isfinite(theta) || !Eigen::Map<const Eigen::VectorXd>(u, dummy).allFinite()) break;
  }
  return l;
}

}  // namespace baseline

/// The seed scene's problem after the pile has settled: the default WorldDef (100 circles
/// of r = 1 in the 30 × 30 box, μ = 0.5, Δt = 0.01), 400 steps of "pgs" with 200 sweeps,
/// then collide + assemble once more. Built on first use and immutable afterwards (Google
/// Benchmark calls a benchmark function several times; stepping the world each time would
/// dominate the run).
const dc::LcpProblem& seed_scene_problem() {
  static const dc::LcpProblem problem = [] {
    dc::World world(dc::default_world_def());
    const auto solver = dc::make_solver("pgs");
    dc::SolverOptions o;
    o.max_sweeps = 200;
    o.tolerance = 0.0;
    o.record_theta = false;
    for (int k = 0; k < 400; ++k) world.step(*solver, o);
    world.collide();
    world.assemble();
    return world.ensure_assembled_matrix();  // A for BM_SeedScenePgsAssembled
  }();
  return problem;
}

/// Times one solve of `sweeps` sweeps from λ⁰ = 0 per benchmark iteration and reports
/// ns_per_row_sweep; max_diff_vs_baseline = max_i |λ_i − λ_i(baseline kernel)| after the
/// same sweeps (0 means bit-identical iterates up to the sign of zero).
template <class Solve>
void time_solve(benchmark::State& state, const dc::LcpProblem& p, int sweeps, Solve&& solve) {
  const Eigen::VectorXd check = solve();
  for (auto _ : state) {
    Eigen::VectorXd l = solve();
    benchmark::DoNotOptimize(l.data());
  }
  state.counters["rows"] = p.rows();
  state.counters["max_diff_vs_baseline"] = (check - baseline::solve(p, sweeps)).cwiseAbs().maxCoeff();
  state.counters["ns_per_row_sweep"] = benchmark::Counter(
      1e-9 * static_cast<double>(p.rows()) * sweeps * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void run_solver(benchmark::State& state, const dc::LcpProblem& p, int sweeps, const char* solver_name) {
  const auto solver = dc::make_solver(solver_name);
  dc::SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = 0.0;
  o.record_theta = false;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.rows());
  time_solve(state, p, sweeps, [&] { return solver->solve(p, zero, o).lambda; });
}

dc::LcpProblem pile_of(const benchmark::State& s) {
  return pile(static_cast<int>(s.range(0)), static_cast<int>(s.range(2)));
}

void BM_PgsMatrixFree(benchmark::State& s) {
  run_solver(s, pile_of(s), static_cast<int>(s.range(1)), "pgs");
}
void BM_PgsAssembled(benchmark::State& s) {
  run_solver(s, pile_of(s), static_cast<int>(s.range(1)), "pgs-assembled");
}
void BM_PgsBaseline(benchmark::State& s) {
  const dc::LcpProblem p = pile_of(s);
  const int sweeps = static_cast<int>(s.range(1));
  time_solve(s, p, sweeps, [&] { return baseline::solve(p, sweeps); });
}

void sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"bodies", "sweeps", "order"});
  for (int bodies : {100, 1000})
    for (int sweeps : {1, 200}) b->Args({bodies, sweeps, 0});
  b->Args({10000, 200, 0});
  for (int bodies : {100, 1000}) b->Args({bodies, 200, 1});
}

// ---- pgs-colored ------------------------------------------------------------------------
/// Kernel argument of the pgs-colored benchmarks: 0 scalar, 1 AVX2, 2 AVX-512.
dc::PgsColoredKernel kernel_arg(std::int64_t k) {
  return k == 2 ? dc::PgsColoredKernel::Avx512 : k == 1 ? dc::PgsColoredKernel::Avx2 : dc::PgsColoredKernel::Scalar;
}

void run_colored(benchmark::State& state, const dc::LcpProblem& p, int sweeps, dc::PgsColoredKernel kernel,
                 int threads) {
  if (!dc::pgs_colored_kernel_available(kernel)) {
    state.SkipWithError("kernel not available on this CPU");
    return;
  }
  dc::PgsColoredDef def;
  def.kernel = kernel;
  def.threads = threads;
  def.min_batches_per_thread = 0;
  const auto solver = dc::make_pgs_colored(def);
  dc::PgsColoredDef scalar_def;
  scalar_def.kernel = dc::PgsColoredKernel::Scalar;
  dc::SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = 0.0;
  o.record_theta = false;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.rows());
  const Eigen::VectorXd scalar = dc::make_pgs_colored(scalar_def)->solve(p, zero, o).lambda;
  time_solve(state, p, sweeps, [&] { return solver->solve(p, zero, o).lambda; });
  state.counters["max_diff_vs_scalar"] = (solver->solve(p, zero, o).lambda - scalar).cwiseAbs().maxCoeff();
}
void BM_PgsColored(benchmark::State& s) {
  run_colored(s, pile_of(s), static_cast<int>(s.range(1)), kernel_arg(s.range(3)), 1);
}
void colored_sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"bodies", "sweeps", "order", "kernel"});
  for (int kernel : {2, 1, 0})
    for (int bodies : {100, 1000, 10000}) b->Args({bodies, 200, 0, kernel});
  for (int kernel : {2, 1, 0}) b->Args({1000, 1, 0, kernel});
}
double cpu_seconds(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
/// Runs `solve(k)` for the k-th iteration of the benchmark loop and reports the CPU time of
/// the whole process (all threads) and of the calling thread per solve, as cpu_process_ms and
/// cpu_main_ms.
template <class Solve>
void time_solves(benchmark::State& s, Solve&& solve) {
  double cpu_process = 0, cpu_main = 0;
  int k = 0;
  for (auto _ : s) {
    const double p0 = cpu_seconds(CLOCK_PROCESS_CPUTIME_ID), m0 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
    Eigen::VectorXd l = solve(k++);
    benchmark::DoNotOptimize(l.data());
    cpu_process += cpu_seconds(CLOCK_PROCESS_CPUTIME_ID) - p0;
    cpu_main += cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - m0;
  }
  const double n = static_cast<double>(s.iterations());
  s.counters["cpu_process_ms"] = 1e3 * cpu_process / n;
  s.counters["cpu_main_ms"] = 1e3 * cpu_main / n;
}

/// 1 vs 2 threads on the 10,000-body pile (Auto kernel), set-up and residual included. Wall time
/// (UseRealTime) is what a speed-up is, but on a loaded machine it mostly measures preemption;
/// so the benchmark also reports the CPU time of the whole process (all threads) and of the
/// calling thread per solve: with OMP_WAIT_POLICY=passive (waiting threads sleep instead of
/// spinning) the speed-up the 2 threads would have on 2 free cores is ≈ cpu_1thread /
/// max(cpu_main, cpu_process − cpu_main) (load-independent estimate; the barrier wake-up latency
/// is not in it). assembled = 1: the problem carries A (LcpProblem::validate scans it on every
/// solve); 0: J only, as the engine hands it to pgs-colored. sweeps = 1 times the per-solve
/// work around the sweeps; (t(100) − t(1)) / 99 is the time per sweep.
void BM_PgsColoredThreads(benchmark::State& s) {
  dc::LcpProblem p = pile(static_cast<int>(s.range(0)), 0);
  if (s.range(3) == 0) p.A = dc::SparseRowMatrix();
  const int sweeps = static_cast<int>(s.range(1));
  dc::PgsColoredDef def;
  def.threads = static_cast<int>(s.range(2));
  def.min_batches_per_thread = 0;
  const auto solver = dc::make_pgs_colored(def);
  dc::SolverOptions o;
  o.max_sweeps = sweeps;
  o.record_theta = false;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.rows());
  (void)solver->solve(p, zero, o);  // warm-up (thread pool, colouring)
  time_solves(s, [&](int) { return solver->solve(p, zero, o).lambda; });
  const double n = static_cast<double>(s.iterations());
  s.counters["ns_per_row_sweep"] = benchmark::Counter(1e-9 * p.rows() * sweeps * n,
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

/// As BM_PgsColoredThreads (J only, 1 sweep: the work around the sweeps), but the solves alternate
/// between the pile's contacts in body order and interleaved (pile order 1): the same contacts,
/// so the colours are looked up and reused, but never a repeated set (no layout reuse) — the
/// set-up of a step whose contacts changed. Reports the CPU time per solve as BM_PgsColoredThreads.
void BM_PgsColoredAlternating(benchmark::State& s) {
  std::array<dc::LcpProblem, 2> p = {pile(10000, 0), pile(10000, 1)};
  for (auto& q : p) q.A = dc::SparseRowMatrix();
  dc::PgsColoredDef def;
  def.threads = static_cast<int>(s.range(0));
  def.min_batches_per_thread = 0;
  const auto solver = dc::make_pgs_colored(def);
  dc::SolverOptions o;
  o.max_sweeps = 1;
  o.record_theta = false;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p[0].rows());
  (void)solver->solve(p[1], zero, o);
  time_solves(s, [&](int k) { return solver->solve(p[static_cast<size_t>(k % 2)], zero, o).lambda; });
}

/// The colouring alone: ns per contact (counter ns_per_contact), from scratch (reuse = 0) or
/// reusing the previous call's colours: reuse = 1, the same contacts every call (a repeat: one
/// comparison pass); reuse = 2, two sets alternated that differ by one contact in the middle
/// (every call looks each contact up: the general reuse path). threads: the OpenMP threads
/// of the parallel colouring (same colours for every count); counters chunks and boundary =
/// the chunks coloured in parallel and the contacts coloured serially after them. chunk: 0 =
/// the default serial greedy colouring, else the contacts per chunk of the parallel one.
void BM_ContactColoring(benchmark::State& s) {
  const dc::LcpProblem p = pile(static_cast<int>(s.range(0)), 0);
  const std::vector<std::uint8_t> dyn(static_cast<size_t>(p.J.cols() / 3), 1);
  dc::ContactColorer colorer(s.range(1) != 0, static_cast<int>(s.range(3)));
  dc::ContactConstraints other;  // p's contacts without the middle one
  for (int c = 0; c < p.constraints.size(); ++c)
    if (c != p.constraints.size() / 2) other.add(p.constraints[c]);
  const bool alternate = s.range(1) == 2;
  const int threads = static_cast<int>(s.range(2));
  (void)colorer.color(p.constraints, dyn, threads);
  // CPU time of the calling thread and of the process per call (cpu_main_us, cpu_process_us):
  // with 2 threads under load, 1-thread CPU / max(main, process − main) estimates the speed-up
  // on free cores (OMP_WAIT_POLICY=passive, see BM_PgsColoredThreads).
  double cpu_process = 0, cpu_main = 0;
  bool odd = false;
  for (auto _ : s) {
    const double p0 = cpu_seconds(CLOCK_PROCESS_CPUTIME_ID), m0 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
    benchmark::DoNotOptimize(colorer.color(alternate && odd ? other : p.constraints, dyn, threads).colors);
    cpu_process += cpu_seconds(CLOCK_PROCESS_CPUTIME_ID) - p0;
    cpu_main += cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - m0;
    odd = !odd;
  }
  s.counters["cpu_process_us"] = 1e6 * cpu_process / static_cast<double>(s.iterations());
  s.counters["cpu_main_us"] = 1e6 * cpu_main / static_cast<double>(s.iterations());
  s.counters["colors"] = colorer.last().colors;
  s.counters["reused"] = colorer.last().reused;
  s.counters["chunks"] = colorer.last().chunks;
  s.counters["boundary"] = colorer.last().boundary;
  s.counters["ns_per_contact"] = benchmark::Counter(
      1e-9 * p.constraints.size() * static_cast<double>(s.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

/// The pile of `bodies` bodies (creation order, no assembled A) and pgs-colored's λ after 200
/// sweeps from zero: the state the residual and Δu⁰ benchmarks below time their products at.
std::pair<dc::LcpProblem, Eigen::VectorXd> pile_at_200_sweeps(int bodies) {
  dc::LcpProblem p = pile(bodies, 0);
  p.A = dc::SparseRowMatrix();
  dc::SolverOptions o;
  o.max_sweeps = 200;
  o.tolerance = 0.0;
  o.record_theta = false;
  Eigen::VectorXd l = dc::make_solver("pgs-colored")->solve(p, Eigen::VectorXd::Zero(p.rows()), o).lambda;
  return {std::move(p), std::move(l)};
}

/// pgs-colored's closing natural residual alone (pgs_colored_products.hpp, one thread) at the
/// 200-sweep λ of the pile; form 0: the solver's (colored::natural_residual), 1: lcp_problem.cpp's
/// natural_residual, the reference it equals bit for bit (counter same_bits = 1). Counter
/// ns_per_row = CPU time / rows.
void BM_PgsColoredResidual(benchmark::State& s) {
  const auto [p, l] = pile_at_200_sweeps(static_cast<int>(s.range(0)));
  Eigen::VectorXd du;
  bool finite = false;
  const bool ours = s.range(1) == 0;
  double r = 0.0;
  for (auto _ : s) {
    r = ours ? dc::colored::natural_residual(p, l, 1, du, finite) : dc::natural_residual(p, l);
    benchmark::DoNotOptimize(r);
  }
  const double ref = dc::natural_residual(p, l);
  s.counters["same_bits"] = std::memcmp(&r, &ref, sizeof r) == 0 ? 1 : 0;
  s.counters["ns_per_row"] = benchmark::Counter(1e-9 * p.rows() * static_cast<double>(s.iterations()),
                                                benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

/// pgs-colored's Δu⁰ = M⁻¹Jᵀλ⁰Δt alone (one thread, into the sweeps' per-body layout) at the
/// 200-sweep λ of the pile; arg form: 0 colored::velocity_change over every row, 1 values_finite
/// then velocity_change skipping the λ_i = 0 rows (two passes over J's values), 2
/// velocity_change_checked (the solve's: one pass, the same bits as 1). Counter ns_per_row = CPU
/// time / rows.
void BM_PgsColoredVelocityChange(benchmark::State& s) {
  const auto [p, l] = pile_at_200_sweeps(static_cast<int>(s.range(0)));
  const int form = static_cast<int>(s.range(1));
  const int bodies = static_cast<int>((p.J.cols() + 2) / 3);
  std::vector<double> du(static_cast<size_t>(dc::colored::kStride) * (bodies + 1));
  Eigen::VectorXd jt;
  bool finite = false;
  for (auto _ : s) {
    if (form == 2)
      dc::colored::velocity_change_checked(p, l, bodies, du.data(), jt, finite);
    else
      dc::colored::velocity_change(p, l, bodies, du.data(), jt, form == 1 && dc::colored::values_finite(p));
    benchmark::DoNotOptimize(du.data());
  }
  s.counters["ns_per_row"] = benchmark::Counter(1e-9 * p.rows() * static_cast<double>(s.iterations()),
                                                benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The seed scene: one full 3000-sweep solve (the bench's fixed budget) per iteration.
constexpr int kSeedSweeps = 3000;
void BM_SeedScenePgs(benchmark::State& s) { run_solver(s, seed_scene_problem(), kSeedSweeps, "pgs"); }
void BM_SeedScenePgsBaseline(benchmark::State& s) {
  const dc::LcpProblem& p = seed_scene_problem();
  time_solve(s, p, kSeedSweeps, [&] { return baseline::solve(p, kSeedSweeps); });
}
void BM_SeedScenePgsColored(benchmark::State& s) {
  run_colored(s, seed_scene_problem(), kSeedSweeps, dc::PgsColoredKernel::Avx512, 1);
}
void BM_SeedScenePgsColoredAvx2(benchmark::State& s) {
  run_colored(s, seed_scene_problem(), kSeedSweeps, dc::PgsColoredKernel::Avx2, 1);
}
void BM_SeedScenePgsColoredScalar(benchmark::State& s) {
  run_colored(s, seed_scene_problem(), kSeedSweeps, dc::PgsColoredKernel::Scalar, 1);
}
void BM_SeedScenePgsAssembled(benchmark::State& s) {
  run_solver(s, seed_scene_problem(), kSeedSweeps, "pgs-assembled");
}

BENCHMARK(BM_PgsMatrixFree)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PgsBaseline)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PgsAssembled)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PgsColored)->Apply(colored_sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PgsColoredThreads)
    ->ArgNames({"bodies", "sweeps", "threads", "assembled"})
    ->Args({10000, 100, 1, 1})
    ->Args({10000, 100, 2, 1})
    ->Args({10000, 100, 1, 0})
    ->Args({10000, 100, 2, 0})
    ->Args({10000, 1, 1, 0})
    ->Args({10000, 1, 2, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_PgsColoredAlternating)->ArgNames({"threads"})->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PgsColoredResidual)
    ->ArgNames({"bodies", "form"})
    ->ArgsProduct({{1000, 10000, 40000}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PgsColoredVelocityChange)
    ->ArgNames({"bodies", "form"})
    ->ArgsProduct({{1000, 10000, 40000}, {0, 1, 2}})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ContactColoring)
    ->ArgNames({"bodies", "reuse", "threads", "chunk"})
    ->Args({1000, 0, 1, 0})
    ->Args({1000, 1, 1, 0})
    ->Args({1000, 2, 1, 0})
    ->Args({10000, 0, 1, 0})
    ->Args({10000, 1, 1, 0})
    ->Args({10000, 2, 1, 0})
    ->Args({10000, 0, 1, dc::ContactColorer::kChunk})
    ->Args({10000, 2, 1, dc::ContactColorer::kChunk})
    ->Args({10000, 0, 2, dc::ContactColorer::kChunk})
    ->Args({10000, 2, 2, dc::ContactColorer::kChunk})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SeedScenePgs)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SeedScenePgsColored)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SeedScenePgsColoredAvx2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SeedScenePgsColoredScalar)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SeedScenePgsBaseline)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SeedScenePgsAssembled)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
