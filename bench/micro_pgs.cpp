// Google Benchmark of the PGS sweep, matrix-free ("pgs") and assembled ("pgs-assembled"),
// on a contact-like problem of realistic size: N circles (r = 1, ρ = 1) packed in a
// hexagonal pile, each touching its right and upper-right neighbours (≈ 2 contacts per
// body) plus floor contacts for the bottom row, friction on (2 rows per contact), Δt = 0.01.
// Rows come in body order as a sorted broad phase would give them.
//
// Argument order: 0 = contacts in body order (the engine's order), 1 = interleaved.
// Counter ns_per_row_sweep = CPU time / (rows · sweeps) in nanoseconds (Google Benchmark
// prints it with an "s" suffix because it is an inverted rate; the number is ns). Each benchmark iteration is one
// solve of S sweeps (tolerance 0, θ not recorded), so validation and the "prepare" stage are
// included once per S sweeps; S = 1 shows that fixed overhead, S = 200 the sweep cost.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "dc/engine/lcp_solver.hpp"

namespace {

/// order 0: contacts in body order (each row shares a body with the previous one: the
/// Gauss–Seidel dependency chain is serial); order 1: contacts interleaved with a stride
/// of ~N/7, so consecutive contacts touch different bodies and the CPU can overlap rows.
dc::LcpProblem pile(int bodies, int order) {
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
  if (order == 1) {
    std::vector<C> interleaved;
    const size_t m = contacts.size(), stride = std::max<size_t>(1, m / 7);
    for (size_t start = 0; start < stride; ++start)
      for (size_t c = start; c < m; c += stride) interleaved.push_back(contacts[c]);
    contacts.swap(interleaved);
  }
  const int n = 2 * static_cast<int>(contacts.size());
  std::vector<Eigen::Triplet<double>> trip;
  dc::LcpProblem p;
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
  }
  p.J.resize(n, 3 * bodies);
  p.J.setFromTriplets(trip.begin(), trip.end());
  p.inv_mass.resize(3 * bodies);
  for (int k = 0; k < bodies; ++k) {
    p.inv_mass[3 * k] = p.inv_mass[3 * k + 1] = 1.0 / m;
    p.inv_mass[3 * k + 2] = 1.0 / I;
  }
  p.dt = dt;
  // b = J (u + Δt M⁻¹ F_ext): all bodies at rest under gravity.
  Eigen::VectorXd u = Eigen::VectorXd::Zero(3 * bodies);
  for (int k = 0; k < bodies; ++k) u[3 * k + 1] = -9.81 * dt;
  p.b = p.J * u;
  const dc::SparseRowMatrix Minv_Jt = (p.inv_mass.asDiagonal() * dc::SparseRowMatrix(p.J.transpose())) * dt;
  p.A = p.J * Minv_Jt;
  p.A.makeCompressed();
  return p;
}

void run(benchmark::State& state, const char* solver_name) {
  const dc::LcpProblem p = pile(static_cast<int>(state.range(0)), static_cast<int>(state.range(2)));
  const int sweeps = static_cast<int>(state.range(1));
  const auto solver = dc::make_solver(solver_name);
  dc::SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = 0.0;
  o.record_theta = false;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.rows());
  for (auto _ : state) {
    dc::SolveResult r = solver->solve(p, zero, o);
    benchmark::DoNotOptimize(r.lambda.data());
  }
  state.counters["rows"] = p.rows();
  state.counters["ns_per_row_sweep"] = benchmark::Counter(
      1e-9 * static_cast<double>(p.rows()) * sweeps * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_PgsMatrixFree(benchmark::State& s) { run(s, "pgs"); }
void BM_PgsAssembled(benchmark::State& s) { run(s, "pgs-assembled"); }

void sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"bodies", "sweeps", "order"});
  for (int bodies : {100, 1000})
    for (int sweeps : {1, 200}) b->Args({bodies, sweeps, 0});
  for (int bodies : {100, 1000}) b->Args({bodies, 200, 1});
}

BENCHMARK(BM_PgsMatrixFree)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PgsAssembled)->Apply(sizes)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
