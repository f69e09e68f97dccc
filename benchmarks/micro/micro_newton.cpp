// Google Benchmark of newton-sparse's kernels (dc/lcp/newton_sparse.hpp) on a contact-like
// problem of realistic size: N circles (r = 1, ρ = 1) in a hexagonal pile, each touching its
// right and upper-right neighbours, floor contacts for the bottom row, friction on (2 rows per
// contact, μ = 0.5), Δt = 0.01, at rest under gravity (hex_pile.hpp, shared with micro_pgs).
//
//   BM_NewtonAnalyze/N/S  CHOLMOD's symbolic analysis of A ∪ diag (ordering + symbolic factor)
//   BM_NewtonFactorize/N/S one numeric factorisation of A_FF + ρI (every row free), analysis reused
//   BM_NewtonSolve/N      one solve with that factor (forward + backward substitution)
//   BM_NewtonIteration/N  one whole iteration of the solver (natural map, modes, factorisation,
//                         direction, line search) from the solution perturbed by 1 %, analysis reused
//   BM_BodyFactorize/N/S  one numeric factorisation of prox-newton's body-space matrix
//                         H = M/Δt + Jᵀ D J (D = 1/δ on every row, δ = 1e-2 max A_ii), analysis reused
//   BM_PileSolve/N/solver/start  one whole solve ("a step"): solver 0 newton-sparse, 1 prox-newton;
//                         start 0 = zero, 1 = 2000 nncg sweeps from zero (a warm guess);
//                         to R = 1e-6 of the heaviest weight (the bench's --accuracy), ≤ 300
//                         iterations; counters factorizations, newton (iterations), factor_ms
//                         (newton-sparse), residual_over_target
// N = bodies (1k, 10k, 40k), S = 0 simplicial LDLᵀ (default), 1 supernodal where CHOLMOD picks it. Counter ns_per_contact = CPU time per iteration / contacts [ns].
// DC_CHOLMOD=simplicial|supernodal (docs/solvers.md) overrides S and every solver's own choice
// (scripts/cholmod-pile.sh runs BM_PileSolve both ways, alternated).
//   build/bin/micro_newton --benchmark_min_time=0.2
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "hex_pile.hpp"
#include "solvers/newton_sparse/sparse_factor.hpp"

namespace {

/// The hex pile (hex_pile.hpp) with A formed.
dc::LcpProblem pile(int bodies) {
  dc::LcpProblem p = dc::bench_fixture::hex_pile(bodies);
  p.ensure_assembled_matrix();
  return p;
}

double max_diagonal(const dc::LcpProblem& p) {
  double d = 0.0;
  for (int i = 0; i < p.rows(); ++i) d = std::max(d, p.A.coeff(i, i));
  return d;
}

double ridge(const dc::LcpProblem& p) { return 1e-10 * max_diagonal(p); }

void count(benchmark::State& state, const dc::LcpProblem& p) {
  state.counters["contacts"] = static_cast<double>(p.constraints.size());
  state.counters["ns_per_contact"] = benchmark::Counter(
      static_cast<double>(p.constraints.size()) * 1e-9, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_NewtonAnalyze(benchmark::State& state) {
  const dc::LcpProblem p = pile(static_cast<int>(state.range(0)));
  const std::vector<char> free(static_cast<size_t>(p.rows()), 1);
  dc::NewtonSparseStats st;
  for (auto _ : state) {
    dc::solvers::FreeBlockFactor f(true, false, state.range(1) != 0);
    f.bind(p.A, true);
    f.factorize(free, ridge(p), st);
  }
  state.counters["analyze_ms"] = st.analyze_ms / static_cast<double>(state.iterations());
  state.counters["factor_ms"] = st.factor_ms / static_cast<double>(state.iterations());
  count(state, p);
}

void BM_NewtonFactorize(benchmark::State& state) {
  const dc::LcpProblem p = pile(static_cast<int>(state.range(0)));
  const std::vector<char> free(static_cast<size_t>(p.rows()), 1);
  dc::NewtonSparseStats st;
  dc::solvers::FreeBlockFactor f(true, true, state.range(1) != 0);
  f.bind(p.A, true);
  f.factorize(free, ridge(p), st);  // the analysis, outside the timed loop
  for (auto _ : state) benchmark::DoNotOptimize(f.factorize(free, ridge(p), st));
  count(state, p);
}

void BM_NewtonSolve(benchmark::State& state) {
  const dc::LcpProblem p = pile(static_cast<int>(state.range(0)));
  const std::vector<char> free(static_cast<size_t>(p.rows()), 1);
  dc::NewtonSparseStats st;
  dc::solvers::FreeBlockFactor f(true, true);
  f.bind(p.A, true);
  f.factorize(free, ridge(p), st);
  Eigen::VectorXd x;
  const Eigen::VectorXd b(p.b);
  for (auto _ : state) {
    f.solve(b, x);
    benchmark::DoNotOptimize(x.data());
  }
  count(state, p);
}

void BM_NewtonIteration(benchmark::State& state) {
  const dc::LcpProblem p = pile(static_cast<int>(state.range(0)));
  dc::NewtonSparseSolver solver;
  dc::SolverOptions o;
  o.record_theta = false;
  o.max_sweeps = 100;
  const Eigen::VectorXd star = solver.solve(p, {}, o).lambda;
  Eigen::VectorXd start = star;
  for (int i = 0; i < start.size(); ++i) start[i] *= 1.0 + 0.01 * std::sin(1.0 + i);
  o.max_sweeps = 1;
  o.exact_tolerance = 1e-300;  // always one iteration
  for (auto _ : state) benchmark::DoNotOptimize(solver.solve(p, start, o).lambda.data());
  const dc::NewtonSparseStats st = solver.last_stats();
  state.counters["factor_ms"] = st.factor_ms;
  state.counters["solve_ms"] = st.solve_ms;
  state.counters["total_ms"] = st.total_ms;
  count(state, p);
}

/// prox-newton's body-space matrix H = M/Δt + Jᵀ D J with D = 1/δ on every row (the pattern of
/// a pass where every row is on a quadratic piece), δ = 1e-2 max_i A_ii as its first pass.
dc::SparseRowMatrix body_matrix(const dc::LcpProblem& p) {
  const double delta = 1e-2 * max_diagonal(p);
  dc::SparseRowMatrix JtJ = (p.J.transpose() * p.J).eval() / delta;
  dc::SparseRowMatrix M(p.J.cols(), p.J.cols());
  M.setIdentity();
  for (int k = 0; k < M.rows(); ++k) M.coeffRef(k, k) = 1.0 / (p.inv_mass[k] * p.dt);
  dc::SparseRowMatrix H = M + JtJ;
  H.makeCompressed();
  return H;
}

void BM_BodyFactorize(benchmark::State& state) {
  const dc::LcpProblem p = pile(static_cast<int>(state.range(0)));
  const dc::SparseRowMatrix H = body_matrix(p);
  const std::vector<char> free(static_cast<size_t>(H.rows()), 1);
  dc::NewtonSparseStats st;
  dc::solvers::FreeBlockFactor f(true, true, state.range(1) != 0);
  f.bind(H, true);
  f.factorize(free, 0.0, st);  // the analysis, outside the timed loop
  for (auto _ : state) benchmark::DoNotOptimize(f.factorize(free, 0.0, st));
  state.counters["unknowns"] = static_cast<double>(H.rows());
  count(state, p);
}

void BM_PileSolve(benchmark::State& state) {
  const dc::LcpProblem p = pile(static_cast<int>(state.range(0)));
  const bool prox = state.range(1) != 0;
  dc::SolverOptions o;
  o.record_theta = false;
  o.max_sweeps = 300;
  Eigen::VectorXd start = Eigen::VectorXd::Zero(p.rows());
  if (state.range(2) != 0) {  // nncg does not factorise: the same guess whatever DC_CHOLMOD says
    dc::SolverOptions warm = o;
    warm.max_sweeps = 2000;
    start = dc::make_solver("nncg")->solve(p, start, warm).lambda;
  }
  o.tolerance = 1e-6 * M_PI * 9.81;  // R = 1e-6 of the heaviest weight (every circle has m = π)
  dc::NewtonSparseSolver ns;
  dc::ProxNewtonSolver pn;
  dc::LcpSolver& solver = prox ? static_cast<dc::LcpSolver&>(pn) : ns;
  dc::SolveResult r;
  for (auto _ : state) r = solver.solve(p, start, o);
  state.counters["newton"] = r.sweeps;
  state.counters["residual_over_target"] = r.residual / o.tolerance;
  if (prox) {
    const dc::ProxNewtonStats st = pn.last_stats();
    state.counters["factorizations"] = st.factorizations;
    state.counters["passes"] = st.outer;
  } else {
    const dc::NewtonSparseStats st = ns.last_stats();
    state.counters["factorizations"] = st.factorizations;
    state.counters["factor_ms"] = st.factor_ms;
  }
  count(state, p);
}

}  // namespace

// Second argument: 0 = simplicial LDLᵀ (the default), 1 = CHOLMOD's choice (supernodal, BLAS).
BENCHMARK(BM_NewtonAnalyze)->ArgsProduct({{1000, 10000, 40000}, {0, 1}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NewtonFactorize)->ArgsProduct({{1000, 10000, 40000}, {0, 1}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NewtonSolve)->Arg(1000)->Arg(10000)->Arg(40000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NewtonIteration)->Arg(1000)->Arg(10000)->Arg(40000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BodyFactorize)->ArgsProduct({{1000, 10000, 40000}, {0, 1}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PileSolve)
    ->ArgNames({"bodies", "solver", "start"})
    ->ArgsProduct({{1000, 10000}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK_MAIN();
