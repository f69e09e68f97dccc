// `deepcontact lcp solve FILE [--kind lcp|fc2d] [--solver NAME] [--sweeps N] [--tol T] [--proximal]`:
// solve one problem (Siconos LCP .dat storage 0/1, Siconos 2D frictional-contact .dat storage
// 0/1/2, FCLIB .hdf5 spacedim 2; docs/lcp.md) and print JSON on stdout: problem, z and w (an
// LCP) or r and u (a frictional problem, FCLIB's names), mu (fc2d only), status, sweeps,
// residual, solve_seconds (CPU time of the solve alone), solver (whose answer it is), route (the
// solvers run, in order), message, comment (the remark after q). Without --solver the route is
// chosen by the problem's kind (dc/lcp/default_route.hpp). A frictional problem is solved as its
// box-friction LCP (r = reactions per contact normal, tangent; u = W r + q; residual = natural
// map of the 2D Coulomb problem). Numbers %.17g, non-finite as null (json_writer.hpp). Exit
// status (docs/cli.md): 0 converged, 3 proven infeasible, 1 any other status or an error.
// `deepcontact lcp convert IN.dat OUT.dat [--storage 0|1] [--block B]` rewrites a file in dense
// (0) or sparse-block (1, square blocks of B rows) storage.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <optional>
#include <span>
#include <string>

#include "commands/cli_common.hpp"
#include "commands/commands.hpp"
#include "dc/bench/json_writer.hpp"
#include "dc/core/error.hpp"
#include "dc/lcp/problem_file.hpp"
#include "dc/io/output_path.hpp"
#include "dc/lcp/dat_file.hpp"
#include "dc/lcp/default_route.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/proximal_point.hpp"

namespace dc::cli {
namespace {

struct LcpSolveArgs {
  std::string file;
  std::string kind;  // "" = detect
  std::string solver;     // "" = the default route by problem kind (default_route.hpp)
  int sweeps = 3000;
  double tol = 1e-10;
  bool proximal = false;  // solve by the proximal-point route around `solver` (proximal_point.hpp)
};

/// CPU seconds of this process so far.
double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::optional<ProblemKind> forced_kind(const std::string& kind) {
  if (kind.empty()) return std::nullopt;
  return parse_problem_kind(kind);
}

/// The JSON of one solve. A frictional problem's vectors carry FCLIB's names: r (reactions)
/// and u = W r + q; an LCP's are z and w = M z + q.
void print_solution(const ProblemFile& f, const SolveResult& r, double seconds, const std::string& solver,
                    const std::string& route) {
  const Eigen::VectorXd w = lcp_velocity(f.lcp, r.lambda);
  auto span = [](const Eigen::VectorXd& v) { return std::span<const double>(v.data(), static_cast<std::size_t>(v.size())); };
  const bool fc2d = f.kind == ProblemKind::Fc2d;
  JsonWriter j;
  j.begin_object();
  j.key("problem").value(to_string(f.kind));
  j.key(fc2d ? "r" : "z").array(span(r.lambda));
  j.key(fc2d ? "u" : "w").array(span(w));
  if (fc2d) j.key("mu").array(span(f.fc2d.mu));
  j.key("status").value(to_string(r.status));
  j.key("sweeps").value(r.sweeps);
  j.key("residual").value(r.residual);
  j.key("solve_seconds").value(seconds);
  j.key("solver").value(solver);
  j.key("route").value(route);
  j.key("message").value(r.message);
  j.key("comment").value(f.comment);
  j.end_object();
  const std::string out = j.str();
  std::fputs(out.c_str(), stdout);
  std::fflush(stdout);
}

struct Solved {
  SolveResult result;
  std::string solver, route;
};

/// --solver NAME [--proximal]: that solver with the command line's limits.
Solved solve_named(const ProblemFile& f, const LcpSolveArgs& a) {
  const SolverId id = SolverId::parse(a.solver);
  SolverOptions o;
  o.max_sweeps = a.sweeps;
  o.tolerance = a.tol;
  o.record_theta = false;
  if (!a.proximal) {
    SolveResult r = make_solver(id)->solve(f.lcp, Eigen::VectorXd(), o);
    return {std::move(r), a.solver, a.solver};
  }
  ProximalPointDef route;
  route.inner_solver = id;
  SolverOptions exact;  // the route solves to the solution test (solution_target), its own limits
  exact.record_theta = false;
  const std::string name = "proximal:" + a.solver;
  return {solve_proximal_point(f.lcp, Eigen::VectorXd(), exact, route), name, name};
}

/// No --solver: the default route by problem kind (default_route.hpp); --proximal skips its plain run.
Solved solve_default(const ProblemFile& f, const LcpSolveArgs& a) {
  SolverOptions o;
  o.max_sweeps = a.sweeps;
  o.tolerance = a.tol;
  DefaultRouteDef def;
  def.plain = !a.proximal;
  RouteResult r = solve_with_default_route(f.lcp, o, def);
  return {std::move(r.result), r.solver, r.route};
}

void run_lcp_solve(const LcpSolveArgs& a) {
  if (!a.solver.empty()) (void)make_solver(SolverId::parse(a.solver));  // ConfigError for an unknown name, before reading
  if (a.sweeps < 0) throw ConfigError("--sweeps must be >= 0");
  if (!(a.tol >= 0) || !std::isfinite(a.tol)) throw ConfigError("--tol must be finite and >= 0");
  const ProblemFile f = read_problem_file(a.file, forced_kind(a.kind));
  if (!f.comment.empty())
    std::fprintf(stderr, "deepcontact: note: %s: the text after %s was ignored (reported as \"comment\")\n",
                 a.file.c_str(), f.kind == ProblemKind::Lcp ? "q" : "mu");
  const double t0 = cpu_seconds();
  const Solved s = a.solver.empty() ? solve_default(f, a) : solve_named(f, a);
  const double seconds = cpu_seconds() - t0;
  print_solution(f, s.result, seconds, s.solver, s.route);
  switch (s.result.status) {
    case SolveStatus::Converged: exit_status() = 0; break;
    case SolveStatus::Infeasible: exit_status() = 3; break;
    default: exit_status() = 1; break;
  }
}

struct LcpConvertArgs {
  std::string in, out;
  std::string kind;    // "" = detect
  std::string format;  // "" = from OUT's name: .hdf5 → fclib, otherwise siconos-lcp
  int storage = 0;
  int block = 0;
};

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

void run_lcp_convert(const LcpConvertArgs& a) {
  if (a.storage != 0 && a.storage != 1) throw ConfigError("--storage must be 0 (dense) or 1 (sparse block)");
  if (a.block < 0) throw ConfigError("--block must be >= 1");
  check_output_file(a.out);
  ProblemWriteDef def;
  // Without --format: FCLIB for OUT.hdf5 / OUT.h5, else the Siconos LCP .dat (a frictional
  // problem then needs --format siconos-fc, said below). OUT's name must say what it holds.
  def.format = !a.format.empty() ? parse_problem_format(a.format)
               : ends_with(a.out, ".hdf5") || ends_with(a.out, ".h5") ? ProblemFormat::Fclib
                                                                      : ProblemFormat::SiconosLcp;
  if (*def.format == ProblemFormat::Fclib) check_output_extension("OUT", a.out, kHdf5Extensions, "an FCLIB file");
  else check_output_extension("OUT", a.out, {".dat"}, "a Siconos .dat file");
  def.storage = a.storage;
  def.block = a.block;
  const ProblemFile f = read_problem_file(a.in, forced_kind(a.kind));
  if (def.format == ProblemFormat::SiconosLcp && f.kind == ProblemKind::Fc2d)
    throw ConfigError(a.in + ": a frictional problem is written with --format siconos-fc or as OUT.hdf5 (FCLIB)");
  write_problem_file(a.out, f, def);
  if (!f.comment.empty())
    std::fprintf(stderr, "deepcontact: note: %s: the text after %s was not copied\n", a.in.c_str(),
                 f.kind == ProblemKind::Lcp ? "q" : "mu");
}

}  // namespace

void add_lcp_command(CLI::App& app) {
  auto* lcp = app.add_subcommand("lcp", "LCP and 2D frictional-contact problems from files (Siconos .dat, FCLIB .hdf5)");
  lcp->require_subcommand(1);
  auto args = std::make_shared<LcpSolveArgs>();
  auto* solve = lcp->add_subcommand(
      "solve",
      "Solve an LCP (w = M z + q, z >= 0, w >= 0, z'w = 0) or a 2D frictional-contact problem (u = W r + q, "
      "Coulomb per contact; solved as its box-friction LCP) read from a Siconos .dat or FCLIB .hdf5 file and "
      "print {\"problem\", \"z\", \"w\" (LCP) or \"r\", \"u\", \"mu\" (frictional), \"status\", \"sweeps\", "
      "\"residual\", \"solve_seconds\", \"solver\", \"route\", \"message\", \"comment\"} as JSON. Exit status: 0 converged (z passes the solution test), 3 infeasible (proved: Farkas certificate or exhaustive "
      "enumeration), 1 otherwise or on error. See docs/lcp.md.");
  solve->add_option("file", args->file,
                    "Problem file: Siconos LCP .dat, Siconos 2D frictional-contact .dat, or FCLIB .hdf5 (spacedim 2)")
      ->required();
  solve->add_option("--kind", args->kind, "Force the kind of a .dat file: lcp or fc2d (default: detected)")
      ->check(CLI::IsMember({"lcp", "fc2d"}));
  std::string names;
  for (const auto& n : solver_names()) names += (names.empty() ? "" : ", ") + n;
  solve->add_option("--solver", args->solver,
                    "Solver: " + names +
                        " (exact: lemke, newton). Default: by problem kind, lemke for an LCP, prox-newton for a "
                        "frictional problem, then newton-sparse and the proximal route where it fails (JSON \"route\")");
  solve->add_option("--sweeps", args->sweeps, "Sweep/iteration limit (pivots for lemke are capped at 50n)")
      ->capture_default_str();
  solve->add_option("--tol", args->tol,
                    "Iterative solvers: stop when max change per sweep <= tol (0 = run all sweeps); "
                    "newton-sparse, prox-newton: natural-map residual target (0 = 1e-9*max(1,|q|inf)); "
                    "lemke/newton solve to 1e-9*max(1,|q|inf)")
      ->capture_default_str();
  solve->add_flag("--proximal", args->proximal,
                  "Solve by the proximal-point route around --solver (e.g. newton-sparse; without --solver: lemke "
                  "for an LCP, the default route without its plain newton-sparse run for a frictional problem): "
                  "shifted problems A + dI, for singular or slightly "
                  "indefinite W; to 1e-9*max(1,|q|inf), --sweeps/--tol unused");
  solve->callback([args] { run_lcp_solve(*args); });

  auto cargs = std::make_shared<LcpConvertArgs>();
  auto* convert = lcp->add_subcommand(
      "convert",
      "Rewrite a problem file: OUT.hdf5 = FCLIB, --format siconos-fc = Siconos frictional-contact .dat, otherwise "
      "an LCP .dat in dense (0) or sparse-block (1) storage");
  convert->add_option("in", cargs->in, "input file (.dat or FCLIB .hdf5)")->required();
  convert->add_option("out", cargs->out, "output file")->required();
  convert->add_option("--kind", cargs->kind, "Force the kind of a .dat input: lcp or fc2d (default: detected)")
      ->check(CLI::IsMember({"lcp", "fc2d"}));
  convert->add_option("--format", cargs->format,
                      "siconos-lcp, siconos-fc or fclib (default: fclib when OUT ends in .hdf5 or .h5, else siconos-lcp; OUT must end in .dat or .hdf5/.h5 to match)")
      ->check(CLI::IsMember({"siconos-lcp", "siconos-fc", "fclib"}));
  convert->add_option("--storage", cargs->storage, "0 = dense, 1 = sparse block (Siconos SparseBlockStructuredMatrix)")
      ->capture_default_str();
  convert->add_option("--block", cargs->block, "storage 1: rows/columns per square block (0 = one block of n)")
      ->capture_default_str();
  convert->callback([cargs] { run_lcp_convert(*cargs); });
}

}  // namespace dc::cli
