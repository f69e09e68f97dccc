// siconos_compare: the same 2D frictional-contact problems solved by Siconos numerics 4.4's 2D
// solvers and by ours, from the same start (r = 0), each measured afterwards by one residual
// computed here, independently of both libraries (docs/lcp.md "Side by side with Siconos").
//
//   siconos_compare [--ours newton,newton-sparse,nncg,proximal:newton-sparse] [--siconos nsgs,cpg,lemke] [--tol 1e-8]
//                   [--max-iter 100000] [--repeat 3] [--dense-limit 1400] [--csv FILE] FILE...
//
// FILE: Siconos frictional-contact .dat or FCLIB .hdf5. Our reader gives W, q, μ; Siconos
// gets the same problem through its own readers: a .dat through frictionContact_new_from_filename
// (the original file, checked against ours: q and μ bit-equal, W x equal to round-off for a
// random x) and an FCLIB file through libfclib's fclib_read_local (checked bit-equal to ours).
// NSGS then runs in Siconos' sparse-block storage (2 × 2 blocks; our %.17g storage-1 copy of W
// read back by Siconos), CPG and Lemke in dense storage when 2nc ≤ --dense-limit.
//
// Equal residual: Siconos' tolerance is max(--tol, the residual of our best solver — the fastest
// that reached --tol, else the most accurate), so that its iterative solvers stop where ours did
// (or at --tol when ours are more accurate); a summary line gives NSGS / best of ours.
// "proximal:NAME" in --ours is the proximal-point route around NAME (proximal_point.hpp). Our
// iterative solvers (pgs, nncg, …) run the fewest sweeps whose iterate reaches --tol on the
// residual below (found by one untimed run with a checkpoint after every sweep; 3000 at most).
//
// Residual (the same for every row of the table): De Saxcé's natural map of the Coulomb
// problem, ‖r − P_K(r − (u + μ|u_t| e_n))‖₂ / max(‖r‖₂, ‖u‖₂, ‖q‖₂) with u = W r + q and K
// the cone |r_t| ≤ μ r_n (not divided when that maximum is below machine epsilon): zero
// exactly at a solution, and scaled as Siconos scales its own error, so that its tolerance
// means the same number here. Times are CPU seconds of the solve call
// alone (process CPU clock; run with OPENBLAS_NUM_THREADS=1), the median of --repeat runs.
// "iterations": Siconos' iparam[ITER_DONE]; ours SolveResult::sweeps. Prints a table, and
// one CSV line per solve to --csv.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "dc/lcp/problem_file.hpp"
#include "dc/lcp/fc2d_dat_file.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/proximal_point.hpp"

extern "C" {
#include <fclib.h>
}
#include "Friction_cst.h"
#include "FrictionContactProblem.h"
#include "NonSmoothDrivers.h"
#include "NumericsMatrix.h"
#include "SolverOptions.h"

namespace {

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// De Saxcé natural-map residual, relative to ‖q‖₂ (see the header comment).
double independent_residual(const dc::Fc2dProblem& p, const Eigen::VectorXd& r) {
  const Eigen::VectorXd u = p.W * r + p.q;
  double sum = 0;
  for (int c = 0; c < p.contacts(); ++c) {
    const double mu = p.mu[c], rn = r[2 * c], rt = r[2 * c + 1];
    double xn = rn - (u[2 * c] + mu * std::abs(u[2 * c + 1])), xt = rt - u[2 * c + 1];
    const double nt = std::abs(xt);
    if (mu * nt <= -xn) {  // in the polar cone: projects to 0
      xn = 0;
      xt = 0;
    } else if (nt > mu * xn) {  // outside K: onto its boundary
      xn = (mu * nt + xn) / (mu * mu + 1.0);
      xt = mu * xn * (xt > 0 ? 1.0 : xt < 0 ? -1.0 : 0.0);
    }
    sum += (rn - xn) * (rn - xn) + (rt - xt) * (rt - xt);
  }
  // Relative as Siconos scales its error (fc2d_compute_error): by max(‖r‖, ‖u‖, ‖q‖) unless
  // that is below machine epsilon (problems with q = 0 to round-off, whose solution is r ≈ 0).
  const double scale = std::max({r.norm(), u.norm(), p.q.norm()});
  return scale > 2.220446049250313e-16 ? std::sqrt(sum) / scale : std::sqrt(sum);
}

struct Outcome {
  std::string file, side, solver, status;
  int contacts = 0;
  double seconds = 0, residual = 0;
  long iterations = 0;
  Eigen::VectorXd r;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// A Siconos problem whose M is in dense storage, built from ours (column-major copy).
FrictionContactProblem* siconos_dense(const dc::Fc2dProblem& p) {
  const int n = static_cast<int>(p.q.size());
  NumericsMatrix* M = NM_create(NM_DENSE, n, n);
  const Eigen::MatrixXd W(p.W);
  std::copy(W.data(), W.data() + W.size(), M->matrix0);
  auto* q = static_cast<double*>(malloc(sizeof(double) * static_cast<size_t>(n)));
  auto* mu = static_cast<double*>(malloc(sizeof(double) * static_cast<size_t>(p.contacts())));
  std::copy(p.q.data(), p.q.data() + n, q);
  std::copy(p.mu.data(), p.mu.data() + p.contacts(), mu);
  return frictionContactProblem_new_with_data(2, p.contacts(), M, q, mu);
}

/// A Siconos problem in sparse-block storage: our exact storage-1 text read by Siconos.
FrictionContactProblem* siconos_sparse_block(const dc::Fc2dProblem& p, const std::string& tmp) {
  dc::write_fc2d_dat(tmp, p, dc::Fc2dStorage::SparseBlock);
  FrictionContactProblem* s = frictionContact_new_from_filename(tmp.c_str());
  std::filesystem::remove(tmp);
  if (!s || s->M->storageType != NM_SPARSE_BLOCK) throw std::runtime_error("Siconos did not read our storage-1 copy");
  return s;
}

Outcome run_siconos(const std::string& method, FrictionContactProblem* sp, const dc::Fc2dProblem& p, double tol,
                    int max_iter, int repeat) {
  const int id = method == "nsgs" ? SICONOS_FRICTION_2D_NSGS
                 : method == "cpg" ? SICONOS_FRICTION_2D_CPG
                                   : SICONOS_FRICTION_2D_LEMKE;
  Outcome o;
  o.side = "siconos";
  o.solver = method;
  std::vector<double> times;
  for (int k = 0; k < repeat; ++k) {
    SolverOptions* opt = solver_options_create(id);
    opt->iparam[SICONOS_IPARAM_MAX_ITER] = max_iter;
    opt->dparam[SICONOS_DPARAM_TOL] = tol;
    std::vector<double> r(static_cast<size_t>(p.q.size()), 0.0), u(static_cast<size_t>(p.q.size()), 0.0);
    const double t0 = cpu_seconds();
    const int info = fc2d_driver(sp, r.data(), u.data(), opt);
    times.push_back(cpu_seconds() - t0);
    o.iterations = opt->iparam[SICONOS_IPARAM_ITER_DONE];
    o.status = info == 0 ? "converged" : "info " + std::to_string(info);
    o.r = Eigen::Map<Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size()));
    solver_options_delete(opt);
  }
  o.seconds = median(times);
  o.residual = independent_residual(p, o.r);
  return o;
}

bool is_exact(const std::string& name) {
  return name == "newton" || name == "newton-sparse" || name == "lemke" || name.starts_with("proximal:");
}

/// An iterative solver (pgs, nncg, …) at equal residual: the fewest sweeps whose iterate has
/// independent_residual ≤ tol, found by one run with a checkpoint after every sweep (not
/// timed); `max_sweeps` when no sweep reaches it.
int sweeps_to_reach(dc::LcpSolver& solver, const dc::LcpProblem& lcp, const dc::Fc2dProblem& p, double tol,
                    int max_sweeps) {
  dc::SolverOptions opt;
  opt.record_theta = false;
  opt.max_sweeps = max_sweeps;
  for (int k = 1; k <= max_sweeps; ++k) opt.checkpoints.push_back(k);
  int first = max_sweeps;
  opt.on_checkpoint = [&](int k, const Eigen::VectorXd& lambda) {
    if (k < first && independent_residual(p, lambda) <= tol) first = k;
  };
  solver.solve(lcp, Eigen::VectorXd(), opt);
  return first;
}

/// One of our solvers by name; "proximal:NAME" = the proximal-point route around NAME
/// (dc/lcp/proximal_point.hpp), to the exact tolerance. Iterative solvers run the sweeps
/// that reach `tol` (sweeps_to_reach, at most 3000), exact ones to their own tolerance.
Outcome run_ours(const std::string& name, const dc::Fc2dProblem& p, double tol, int repeat) {
  const dc::LcpProblem lcp = dc::fc2d_to_lcp(p);
  const bool proximal = name.starts_with("proximal:");
  dc::ProximalPointDef route;
  if (proximal) route.inner_solver = dc::SolverId::parse(name.substr(9));
  const auto solver = proximal ? dc::make_solver(route.inner_solver) : dc::make_solver(name);
  dc::SolverOptions opt;
  opt.record_theta = false;
  if (!is_exact(name)) opt.max_sweeps = sweeps_to_reach(*solver, lcp, p, tol, opt.max_sweeps);
  Outcome o;
  o.side = "ours";
  o.solver = name;
  std::vector<double> times;
  for (int k = 0; k < repeat; ++k) {
    const double t0 = cpu_seconds();
    const dc::SolveResult r =
        proximal ? dc::solve_proximal_point(lcp, Eigen::VectorXd(), opt, route) : solver->solve(lcp, Eigen::VectorXd(), opt);
    times.push_back(cpu_seconds() - t0);
    o.r = r.lambda;
    o.iterations = r.sweeps;
    o.status = dc::to_string(r.status);
  }
  o.seconds = median(times);
  o.residual = independent_residual(p, o.r);
  return o;
}

/// Our best result: the fastest of those that reached `tol` (the Siconos-scaled residual), or
/// the most accurate when none did. `rows` holds ours only and is not empty.
Outcome best_of(const std::vector<Outcome>& rows, double tol) {
  const Outcome* best = &rows.front();
  for (const Outcome& o : rows) {
    const bool ok = o.residual <= tol, best_ok = best->residual <= tol;
    if ((ok && !best_ok) || (ok && best_ok && o.seconds < best->seconds) || (!ok && !best_ok && o.residual < best->residual))
      best = &o;
  }
  return *best;
}

/// Checks that Siconos' (or libfclib's) reading of the original file is ours; prints one line.
void check_readers_agree(const std::string& path, const dc::ProblemFile& f) {
  const dc::Fc2dProblem& p = f.fc2d;
  if (f.format == dc::ProblemFormat::Fclib) {
    fclib_local* fl = fclib_read_local(path.c_str());
    if (!fl) throw std::runtime_error(path + ": libfclib cannot read it");
    const dc::Fc2dProblem theirs = dc::fc2d_from_fclib([&] {
      dc::FclibLocalProblem x;
      x.rows = fl->W->m;
      if (fl->W->nz != -1) throw std::runtime_error(path + ": libfclib gave a non-CSC W");
      x.col_start.assign(fl->W->p, fl->W->p + fl->W->n + 1);
      x.row_index.assign(fl->W->i, fl->W->i + x.col_start.back());
      x.values.assign(fl->W->x, fl->W->x + x.col_start.back());
      x.q.assign(fl->q, fl->q + x.rows);
      x.mu.assign(fl->mu, fl->mu + x.rows / 2);
      return x;
    }());
    fclib_delete_local(fl);
    const bool same = Eigen::MatrixXd(theirs.W - p.W).cwiseAbs().maxCoeff() == 0.0 && theirs.q == p.q && theirs.mu == p.mu;
    std::printf("  libfclib's fclib_read_local: W, q, mu %s ours\n", same ? "bit-equal to" : "DIFFER from");
    return;
  }
  FrictionContactProblem* s = frictionContact_new_from_filename(path.c_str());
  const int n = static_cast<int>(p.q.size());
  std::mt19937_64 gen(1);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i) x[i] = U(gen);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(n);
  NM_gemv(1.0, s->M, x.data(), 0.0, y.data());
  const double dw = (y - p.W * x).lpNorm<Eigen::Infinity>() / std::max(1e-300, (p.W * x).lpNorm<Eigen::Infinity>());
  const bool qmu = Eigen::Map<Eigen::VectorXd>(s->q, n) == p.q && Eigen::Map<Eigen::VectorXd>(s->mu, p.contacts()) == p.mu;
  std::printf("  Siconos' frictionContact_new_from_filename: q, mu %s; |W x - ours| / |W x| = %.1e\n",
              qmu ? "bit-equal" : "DIFFER", dw);
  frictionContactProblem_free(s);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Siconos numerics' 2D solvers vs ours on the same frictional-contact problems"};
  std::vector<std::string> files, ours{"newton"}, theirs{"nsgs", "cpg", "lemke"};
  double tol = 1e-8;
  int max_iter = 100000, repeat = 3, dense_limit = 1400;
  std::string csv;
  app.add_option("files", files, "Siconos FC .dat or FCLIB .hdf5 files")->required();
  app.add_option("--ours", ours, "our solvers (comma-separated)")->delimiter(',');
  app.add_option("--siconos", theirs, "Siconos 2D solvers: nsgs, cpg, lemke")->delimiter(',');
  app.add_option("--tol", tol, "Siconos' tolerance (its own relative error), raised to our solvers' worst residual")
      ->capture_default_str();
  app.add_option("--max-iter", max_iter, "Siconos' iteration limit")->capture_default_str();
  app.add_option("--repeat", repeat, "runs per solve (median time)")->capture_default_str();
  app.add_option("--dense-limit", dense_limit, "largest 2nc for the dense solvers (cpg, lemke)")->capture_default_str();
  app.add_option("--csv", csv, "append one CSV line per solve");
  CLI11_PARSE(app, argc, argv);
  std::ofstream out;
  if (!csv.empty()) {
    const bool fresh = !std::filesystem::exists(csv);
    out.open(csv, std::ios::app);
    if (fresh) out << "file,contacts,side,solver,status,iterations,cpu_seconds,residual,max_dr_vs_first\n";
  }
  const std::string tmp = (std::filesystem::temp_directory_path() / ("siconos_compare_" + std::to_string(getpid()) + ".dat")).string();
  for (const std::string& path : files) {
    const dc::ProblemFile f = dc::read_problem_file(path);
    if (f.kind != dc::ProblemKind::Fc2d) {
      std::printf("%s: not a frictional problem, skipped\n", path.c_str());
      continue;
    }
    const dc::Fc2dProblem& p = f.fc2d;
    const std::string name = std::filesystem::path(path).filename().string();
    std::printf("%s: %d contacts, %ld non-zeros in W\n", name.c_str(), p.contacts(), static_cast<long>(p.W.nonZeros()));
    check_readers_agree(path, f);
    std::vector<Outcome> rows;
    for (const std::string& s : ours) rows.push_back(run_ours(s, p, tol, repeat));
    FrictionContactProblem* sbm = siconos_sparse_block(p, tmp);
    FrictionContactProblem* dense = static_cast<int>(p.q.size()) <= dense_limit ? siconos_dense(p) : nullptr;
    // Equal residual: Siconos' iterative solvers stop at max(--tol, the residual of our best
    // solver), measured on the same scale as ours (see independent_residual).
    const Outcome best = best_of(rows, tol);
    const double target = std::max(tol, best.residual);
    for (const std::string& m : theirs) {
      if (m != "nsgs" && !dense) continue;
      rows.push_back(run_siconos(m, m == "nsgs" ? sbm : dense, p, target, max_iter, m == "lemke" ? 1 : repeat));
    }
    frictionContactProblem_free(sbm);
    if (dense) frictionContactProblem_free(dense);
    std::printf("  %-8s %-14s %-12s %10s %12s %10s %12s\n", "side", "solver", "status", "iterations", "CPU s", "residual",
                "|r-r0|/max(1,|r0|)");
    for (Outcome& o : rows) {
      const double dr = (o.r - rows[0].r).lpNorm<Eigen::Infinity>() / std::max(1.0, rows[0].r.lpNorm<Eigen::Infinity>());
      std::printf("  %-8s %-14s %-12s %10ld %12.4g %10.2e %12.2e\n", o.side.c_str(), o.solver.c_str(), o.status.c_str(),
                  o.iterations, o.seconds, o.residual, dr);
      if (out) out << name << ',' << p.contacts() << ',' << o.side << ',' << o.solver << ',' << o.status << ','
                   << o.iterations << ',' << o.seconds << ',' << o.residual << ',' << dr << '\n';
    }
    for (const Outcome& o : rows)
      if (o.side == "siconos" && o.solver == "nsgs")
        std::printf("  best of ours: %s %.4g s (residual %.2e); NSGS %.4g s (%ld iterations, residual %.2e); "
                    "NSGS / ours = %.3g\n",
                    best.solver.c_str(), best.seconds, best.residual, o.seconds, o.iterations, o.residual,
                    o.seconds / std::max(best.seconds, 1e-9));
  }
  return 0;
}
