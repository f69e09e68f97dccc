// `deepcontact lcp solve FILE.dat [--solver NAME] [--sweeps N] [--tol T]`: solve one LCP
// from a Siconos numerics .dat file (dense storage, docs/lcp.md) and print the result as
// JSON on stdout:
//
//     {"z": [...], "w": [...], "status": "converged", "sweeps": k, "residual": r,
//      "solver": "lemke", "message": "..."}
//
// numbers with %.17g (round-trip exact), non-finite as null (JsonWriter, json_writer.hpp). Exit status: 0 when solved (status converged),
// 3 when the solver proved the problem infeasible, 1 for any other status (sweep_limit,
// diverged, failed, invalid_input) and for errors (unreadable/malformed file, unknown
// solver: one line on stderr from main()).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <span>
#include <string>

#include "commands.hpp"
#include "dc/engine/dat_file.hpp"
#include "dc/engine/error.hpp"
#include "dc/engine/lcp_solver.hpp"
#include "json_writer.hpp"

namespace dc::cli {
namespace {

struct LcpSolveArgs {
  std::string file;
  std::string solver = "lemke";
  int sweeps = 3000;
  double tol = 1e-10;
};

void run_lcp_solve(const LcpSolveArgs& a) {
  const auto solver = make_solver(a.solver);  // ConfigError for an unknown name
  if (a.sweeps < 0) throw ConfigError("--sweeps must be >= 0");
  if (!(a.tol >= 0) || !std::isfinite(a.tol)) throw ConfigError("--tol must be finite and >= 0");
  const LcpProblem p = read_lcp_dat(a.file);
  SolverOptions o;
  o.max_sweeps = a.sweeps;
  o.tolerance = a.tol;
  o.record_theta = false;
  const SolveResult r = solver->solve(p, Eigen::VectorXd(), o);
  const Eigen::VectorXd w = lcp_velocity(p, r.lambda);
  JsonWriter j;
  j.begin_object();
  j.key("z").array(std::span<const double>(r.lambda.data(), static_cast<std::size_t>(r.lambda.size())));
  j.key("w").array(std::span<const double>(w.data(), static_cast<std::size_t>(w.size())));
  j.key("status").value(to_string(r.status));
  j.key("sweeps").value(r.sweeps);
  j.key("residual").value(r.residual);
  j.key("solver").value(a.solver);
  j.key("message").value(r.message);
  j.end_object();
  const std::string out = j.str();
  std::fputs(out.c_str(), stdout);
  std::fflush(stdout);
  switch (r.status) {
    case SolveStatus::Converged: exit_status() = 0; break;
    case SolveStatus::Infeasible: exit_status() = 3; break;
    default: exit_status() = 1; break;
  }
}

}  // namespace

void add_lcp_command(CLI::App& app) {
  auto* lcp = app.add_subcommand("lcp", "Linear complementarity problems from files (Siconos .dat)");
  lcp->require_subcommand(1);
  auto args = std::make_shared<LcpSolveArgs>();
  auto* solve = lcp->add_subcommand(
      "solve",
      "Solve w = M z + q, z >= 0, w >= 0, z'w = 0 read from a Siconos numerics .dat file (dense storage 0) "
      "and print {\"z\", \"w\", \"status\", \"sweeps\", \"residual\"} as JSON. Exit status: 0 converged, "
      "3 infeasible (lemke ray termination), 1 otherwise or on error. See docs/lcp.md.");
  solve->add_option("file", args->file, "LCP file in Siconos .dat format (n, 0, n, n, n<TAB>n, M column-major, q)")
      ->required();
  std::string names;
  for (const auto& n : solver_names()) names += (names.empty() ? "" : ", ") + n;
  solve->add_option("--solver", args->solver, "Solver: " + names + " (exact: lemke, newton)")
      ->capture_default_str();
  solve->add_option("--sweeps", args->sweeps, "Sweep/iteration limit (pivots for lemke are capped at 50n)")
      ->capture_default_str();
  solve->add_option("--tol", args->tol,
                    "Iterative solvers: stop when max change per sweep <= tol (0 = run all sweeps); "
                    "lemke/newton solve to 1e-9*max(1,|q|inf)")
      ->capture_default_str();
  solve->callback([args] { run_lcp_solve(*args); });
}

}  // namespace dc::cli
