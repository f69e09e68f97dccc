// Iterations to R against pile depth (docs/solvers.md "prox-newton"): the 12-wide resting piles
// of tests/lcp/solver_test_problems.hpp `deep_pile` (μ = 0.5) at several depths, each solved
// to R = 1e-6 of a body's weight m g by prox-newton (its options.tolerance set to R, so it stops
// there), nncg and pgs (their natural residual read at checkpoints, as the bench's trace does:
// the first at R counts, the checkpoints' own residual evaluations excluded from the CPU time),
// from two starts: λ⁰ = 0, and nncg's iterate after --lead sweeps from 0 (a smooth, global
// error like a warm start's on a settled pile). Per row: iterations to R (sweeps, or for
// prox-newton its lead sweeps and Newton iterations), factorisations, outer passes and CPU ms
// of this thread.
//
//   build/bin/prox_depth --layers 10 20 40 80 --lead 200
#include <time.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "../../tests/lcp/solver_test_problems.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"

namespace {

double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

/// Checkpoints 1..20, then 3 % apart, up to cap (the bench's accuracy checkpoints).
std::vector<int> checkpoints(int cap) {
  std::vector<int> out;
  for (int k = 1; k <= cap; k = k < 20 ? k + 1 : std::max(k + 1, static_cast<int>(std::ceil(k * 1.03)))) out.push_back(k);
  return out;
}

/// A sweep method until its natural residual is ≤ target [N] or cap sweeps: {sweeps, CPU ms}
/// at the first checkpoint at the target, {-1, CPU ms of the whole run} when not reached.
std::pair<int, double> sweeps_to(const char* name, const dc::LcpProblem& p, const Eigen::VectorXd& start,
                                 double target, int cap) {
  const auto solver = dc::make_solver(name);
  dc::SolverOptions o;
  o.max_sweeps = cap;
  o.tolerance = 0.0;
  o.record_theta = false;
  o.checkpoints = checkpoints(cap);
  int reached = -1;
  double callback_ms = 0.0, at_ms = 0.0;
  double t0 = 0.0;
  o.on_checkpoint = [&](int it, const Eigen::VectorXd& lam) {
    if (reached >= 0) return;
    const double c0 = thread_cpu_ms();
    if (dc::natural_residual(p, lam) <= target) {
      reached = it;
      at_ms = c0 - t0 - callback_ms;
    }
    callback_ms += thread_cpu_ms() - c0;
  };
  t0 = thread_cpu_ms();
  (void)solver->solve(p, start, o);
  const double ms = thread_cpu_ms() - t0 - callback_ms;
  return {reached, reached >= 0 ? at_ms : ms};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"prox-newton, nncg and pgs to R on resting piles of growing depth"};
  std::vector<int> layers{10, 20, 40, 80};
  int lead = 200, cap = 100000;
  double accuracy = 1e-6;
  app.add_option("--layers", layers, "pile depths (12 bodies per layer)");
  app.add_option("--lead", lead, "nncg sweeps from 0 for the second start");
  app.add_option("--cap", cap, "sweeps (nncg, pgs) and Newton iterations (prox-newton) at most");
  app.add_option("--accuracy", accuracy, "R: the natural residual's target over a body's weight m g");
  CLI11_PARSE(app, argc, argv);
  constexpr double kMass = M_PI, kGravity = 9.81;  // deep_pile's bodies
  const double target = accuracy * kMass * kGravity;
  std::printf("layers rows start R0 prox_reached prox_lead prox_newton prox_proximal_finish prox_factorisations "
              "prox_passes prox_ms nncg_sweeps nncg_ms pgs_sweeps pgs_ms\n");
  for (const int L : layers) {
    const dc::LcpProblem p = dc::test::deep_pile(12, L, 0.5);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.rows());
    Eigen::VectorXd led = zero;
    if (lead > 0) {
      dc::SolverOptions o;
      o.max_sweeps = lead;
      o.tolerance = 0.0;
      o.record_theta = false;
      led = dc::make_solver("nncg")->solve(p, zero, o).lambda;
    }
    for (const auto& [name, start] : {std::pair<const char*, const Eigen::VectorXd&>{"zero", zero},
                                      std::pair<const char*, const Eigen::VectorXd&>{"nncg", led}}) {
      dc::ProxNewtonSolver prox;
      dc::SolverOptions o;
      o.max_sweeps = cap;
      o.tolerance = target;
      o.record_theta = false;
      const double t0 = thread_cpu_ms();
      const dc::SolveResult r = prox.solve(p, start, o);
      const double ms = thread_cpu_ms() - t0;
      const dc::ProxNewtonStats st = prox.last_stats();
      const auto [nncg_sweeps, nncg_ms] = sweeps_to("nncg", p, start, target, cap);
      const auto [pgs_sweeps, pgs_ms] = sweeps_to("pgs", p, start, target, cap);
      std::printf("%d %d %s %.3g %d %d %d %d %d %d %.1f %d %.1f %d %.1f\n", L, p.rows(), name,
                  dc::natural_residual(p, start) / (kMass * kGravity),
                  dc::natural_residual(p, r.lambda) <= target ? 1 : 0, st.lead_sweeps, st.newton + st.finish_newton,
                  st.proximal_finish_newton, st.factorizations, st.outer, ms, nncg_sweeps, nncg_ms, pgs_sweeps,
                  pgs_ms);
      std::fflush(stdout);
    }
  }
  return 0;
}
