// deepcontact.read_problem / write_problem: problem files of every kind (Siconos LCP and 2D
// frictional-contact .dat, FCLIB .hdf5; dc/lcp/problem_file.hpp, docs/lcp.md).
#include <pybind11/stl.h>

#include <optional>

#include "dc/lcp/problem_file.hpp"
#include "dc/core/error.hpp"
#include "py_common.hpp"

namespace dc::py {
namespace {

pyb::object read_problem(pyb::object path) {
  ProblemFile f = read_problem_file(path_string(path));
  pyb::object out = make_fields();
  out["kind"] = to_string(f.kind);
  out["format"] = to_string(f.format);
  out["comment"] = f.comment;
  pyb::object problem = problem_to_python(std::move(f.lcp));
  out["problem"] = problem;
  if (f.kind == ProblemKind::Fc2d) {
    out["W"] = problem.attr("A");
    out["q"] = problem.attr("b");
    out["mu"] = copy(f.fc2d.mu);
  } else {
    out["W"] = pyb::none();
    out["q"] = pyb::none();
    out["mu"] = pyb::none();
  }
  out["solution"] = f.solution.size() > 0 ? pyb::object(copy(f.solution)) : pyb::none();
  pyb::list guesses;
  for (const Eigen::VectorXd& g : f.guesses) guesses.append(copy(g));
  out["guesses"] = guesses;
  return out;
}

void write_problem(pyb::object path, pyb::object problem, pyb::object solution, pyb::object guesses) {
  const std::string p = path_string(path);
  Fc2dProblem fc;
  std::optional<Fc2dFromLcp> map;  // set when `problem` is an engine LCP: vectors are in its row order
  if (pyb::isinstance<PyProblem>(problem)) {
    map = fc2d_from_lcp(*problem.cast<PyProblem&>().p);
    fc = map->problem;
  } else {
    fc.W = to_sparse(problem["W"], "W");
    fc.q = to_vector(problem["q"], "q");
    fc.mu = to_vector(problem["mu"], "mu");
  }
  auto as_reactions = [&](pyb::handle v, const char* what) {
    // A Result of solve() stands for its λ (the solved rows of `problem`).
    const Eigen::VectorXd x = pyb::isinstance<PyResult>(v) ? v.cast<const PyResult&>().r.lambda : to_vector(v, what);
    return map ? fc2d_reactions(*map, x) : x;
  };
  const Eigen::VectorXd sol = solution.is_none() ? Eigen::VectorXd() : as_reactions(solution, "solution");
  std::vector<Eigen::VectorXd> gs;
  for (pyb::handle g : guesses) gs.push_back(as_reactions(g, "guess"));
  write_fc2d_problem(p, fc, problem_format_for_path(p, ProblemKind::Fc2d), sol, gs);
}

}  // namespace

void bind_problem_file(pyb::module_& m) {
  m.def("read_problem", &read_problem, pyb::arg("path"),
        "Read a problem file: a Siconos LCP .dat, a Siconos 2D frictional-contact .dat (storage 0, 1 or 2) or an "
        "FCLIB local problem .hdf5 (spacedim 2). Returns a Fields with 'kind' ('lcp' or 'fc2d'), 'format' "
        "('siconos-lcp', 'siconos-fc', 'fclib'), 'problem' (a Problem any solver takes: for fc2d the box-friction "
        "LCP, rows per contact normal then tangent), 'W', 'q' (fc2d: views of problem.A, problem.b), 'mu' (one per "
        "contact, fc2d), 'solution' (FCLIB /solution reactions r, or None), 'guesses' (list of FCLIB /guesses r) "
        "and 'comment' (text after the last vector of a .dat). Raises IoError with one line for a malformed file.");
  m.def("write_problem", &write_problem, pyb::arg("path"), pyb::arg("problem"), pyb::arg("solution") = pyb::none(),
        pyb::arg("guesses") = pyb::tuple(),
        "Write a 2D frictional-contact problem: FCLIB when path ends in .hdf5 (or .h5), with solution as /solution "
        "and each guess as a /guesses entry (vectors, or Results of solve()) (u = W r + q is computed for each), otherwise a Siconos frictional-"
        "contact .dat (sparse-block storage; solution and guesses are not written: the format has no place for "
        "them). problem is what read_problem returned (or any mapping with 'W', 'q', 'mu' per contact; vectors "
        "per contact normal, tangent), or a Problem of the engine (World.problem), whose contacts are reordered "
        "per contact (normal, tangent) — its solution and guesses are then given in the Problem's row order.");
}

}  // namespace dc::py
