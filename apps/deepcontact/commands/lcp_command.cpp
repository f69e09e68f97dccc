// `deepcontact lcp solve FILE.dat [--solver NAME] [--sweeps N] [--tol T]`: solve one LCP
// from a Siconos numerics .dat file (dense or sparse-block storage, docs/lcp.md) and print
// the result as JSON on stdout:
//
//     {"z": [...], "w": [...], "status": "converged", "sweeps": k, "residual": r,
//      "solver": "lemke", "message": "...", "comment": "..."}
//
// numbers with %.17g (round-trip exact), non-finite as null (JsonWriter, json_writer.hpp);
// "comment" is the remark after q (empty if none; stderr says it was ignored). Exit status: 0 when solved (status converged), 3 when the
// solver proved the problem infeasible, 1 for any other status (sweep_limit, diverged,
// failed, invalid_input) and for errors (unreadable/malformed file, unknown solver: one
// line on stderr from main()).
//
// `deepcontact lcp convert IN.dat OUT.dat [--storage 0|1] [--block B]` rewrites a file in
// dense (0) or sparse-block (1, square blocks of B rows) storage.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <span>
#include <string>

#include "commands/commands.hpp"
#include "dc/bench/json_writer.hpp"
#include "dc/core/error.hpp"
#include "dc/io/output_path.hpp"
#include "dc/engine/dat_file.hpp"
#include "dc/engine/lcp_solver.hpp"

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
  const DatFile f = read_dat_file(a.file);
  const LcpProblem& p = f.problem;
  if (!f.comment.empty())
    std::fprintf(stderr, "deepcontact: note: %s: the text after q was ignored (reported as \"comment\")\n",
                 a.file.c_str());
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
  j.key("comment").value(f.comment);
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

struct LcpConvertArgs {
  std::string in, out;
  int storage = 0;
  int block = 0;
};

void run_lcp_convert(const LcpConvertArgs& a) {
  if (a.storage != 0 && a.storage != 1) throw ConfigError("--storage must be 0 (dense) or 1 (sparse block)");
  if (a.block < 0) throw ConfigError("--block must be >= 1");
  check_output_file(a.out);
  const DatFile f = read_dat_file(a.in);
  if (a.storage == 0)
    write_lcp_dat(a.out, Eigen::MatrixXd(f.problem.A), f.problem.b);
  else
    write_lcp_dat_blocks(a.out, f.problem.A, f.problem.b, a.block > 0 ? a.block : f.problem.rows());
  if (!f.comment.empty())
    std::fprintf(stderr, "deepcontact: note: %s: the text after q was not copied\n", a.in.c_str());
}

}  // namespace

void add_lcp_command(CLI::App& app) {
  auto* lcp = app.add_subcommand("lcp", "Linear complementarity problems from files (Siconos .dat)");
  lcp->require_subcommand(1);
  auto args = std::make_shared<LcpSolveArgs>();
  auto* solve = lcp->add_subcommand(
      "solve",
      "Solve w = M z + q, z >= 0, w >= 0, z'w = 0 read from a Siconos numerics .dat file (storage 0 = dense "
      "or 1 = sparse block) and print {\"z\", \"w\", \"status\", \"sweeps\", \"residual\", \"comment\"} as "
      "JSON. Exit status: 0 converged, 3 infeasible (proved: Farkas certificate or exhaustive enumeration), "
      "1 otherwise or on error. See docs/lcp.md.");
  solve->add_option("file", args->file, "LCP file in Siconos .dat format (n, storage, n, n, M, q[, remark])")
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

  auto cargs = std::make_shared<LcpConvertArgs>();
  auto* convert = lcp->add_subcommand("convert", "Rewrite a Siconos .dat LCP file in dense (0) or sparse-block (1) storage");
  convert->add_option("in", cargs->in, "input .dat file")->required();
  convert->add_option("out", cargs->out, "output .dat file")->required();
  convert->add_option("--storage", cargs->storage, "0 = dense, 1 = sparse block (Siconos SparseBlockStructuredMatrix)")
      ->capture_default_str();
  convert->add_option("--block", cargs->block, "storage 1: rows/columns per square block (0 = one block of n)")
      ->capture_default_str();
  convert->callback([cargs] { run_lcp_convert(*cargs); });
}

}  // namespace dc::cli
