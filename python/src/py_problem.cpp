// deepcontact.Problem, deepcontact.Result, solve(), solvers(), read_lcp_dat/write_lcp_dat,
// and the exception types (errors are the CLI's one-line messages).
#include <pybind11/stl.h>

#include <limits>

#include "dc/core/error.hpp"
#include "dc/lcp/dat_file.hpp"
#include "py_common.hpp"

namespace dc::py {

void bind_errors(pyb::module_& m) {
  // str(e) is exactly what `deepcontact` prints after "deepcontact: error: ".
  pyb::register_exception<ConfigError>(m, "ConfigError", PyExc_ValueError).attr("__doc__") =
      "A scene key, value, option, solver or starter name is invalid (a ValueError; one line).";
  pyb::register_exception<IoError>(m, "IoError", PyExc_OSError).attr("__doc__") =
      "A file could not be read or written, or is malformed (an OSError; one line naming it).";
  pyb::register_exception<InvalidArgument>(m, "InvalidArgument", PyExc_ValueError).attr("__doc__") =
      "Sizes that disagree or a bad argument to a library call (a ValueError; one line).";
}

namespace {

/// Fixed bounds for rows the caller did not give: [0, +∞) (a standard LCP).
LcpProblem problem_from_python(pyb::handle A, pyb::handle b, pyb::handle lo, pyb::handle hi, pyb::handle mu,
                               pyb::handle normal_row) {
  LcpProblem p;
  p.A = to_sparse(A, "A");
  if (p.A.rows() != p.A.cols())
    throw InvalidArgument("Problem: A must be square (one row and one column per unknown), got " +
                          std::to_string(p.A.rows()) + " x " + std::to_string(p.A.cols()));
  p.b = to_vector(b, "b");
  const int n = p.rows();
  p.lo = lo.is_none() ? Eigen::VectorXd::Zero(n) : to_vector(lo, "lo");
  p.hi = hi.is_none() ? Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity()) : to_vector(hi, "hi");
  p.mu = mu.is_none() ? Eigen::VectorXd::Zero(n) : to_vector(mu, "mu");
  if (normal_row.is_none()) p.normal_row.assign(static_cast<std::size_t>(n), -1);
  else p.normal_row = normal_row.cast<std::vector<int>>();
  if (static_cast<int>(p.normal_row.size()) != n)
    throw InvalidArgument("Problem: normal_row has " + std::to_string(p.normal_row.size()) + " entries, b has " +
                          std::to_string(n));
  p.validate();
  return p;
}

}  // namespace

pyb::object problem_to_python(LcpProblem p) {
  if (p.A.rows() > 0) p.A.makeCompressed();
  if (p.J.rows() > 0) p.J.makeCompressed();
  return pyb::cast(PyProblem{std::make_shared<LcpProblem>(std::move(p))});
}

void bind_problem(pyb::module_& m) {
  pyb::class_<PyProblem>(m, "Problem",
                         "An LCP w = A λ + b, lo ≤ λ ≤ hi (friction rows: |λ_t| ≤ μ λ_n of normal_row). Arrays are "
                         "read-only views into the problem (no copies; copy them to change a problem and make a new "
                         "Problem); A and J are scipy.sparse.csr_matrix views of read-only arrays.")
      .def(pyb::init([](pyb::object A, pyb::object b, pyb::object lo, pyb::object hi, pyb::object mu,
                        pyb::object normal_row) {
             return PyProblem{std::make_shared<LcpProblem>(problem_from_python(A, b, lo, hi, mu, normal_row))};
           }),
           pyb::arg("A"), pyb::arg("b"), pyb::arg("lo") = pyb::none(), pyb::arg("hi") = pyb::none(),
           pyb::arg("mu") = pyb::none(), pyb::arg("normal_row") = pyb::none(),
           "A problem from a dense or scipy.sparse A and b (default bounds: a standard LCP, λ ≥ 0).")
      .def_property_readonly("A",
                             [](pyb::object self) {
                               auto& p = *self.cast<PyProblem&>().p;
                               if (!p.has_assembled_matrix()) {  // assembled from a world: form A once
                                 p.ensure_assembled_matrix();
                                 p.A.makeCompressed();
                               }
                               return csr_view(p.A, self);
                             },
                             "A = J M⁻¹ Jᵀ Δt as a scipy.sparse.csr_matrix view (formed on first access for a "
                             "world's problem).")
      .def_property_readonly("J",
                             [](pyb::object self) -> pyb::object {
                               const auto& p = *self.cast<PyProblem&>().p;
                               if (!p.has_jacobian()) return pyb::none();
                               return csr_view(p.J, self);
                             },
                             "The contact Jacobian J (rows × 3·bodies) as a csr_matrix view, or None for a "
                             "problem given by A alone.")
      .def_property_readonly("b", [](pyb::object self) { return read_only(view(self.cast<PyProblem&>().p->b, self)); },
                             "The constant term b of w = A λ + b (numpy view).")
      .def_property_readonly("lo", [](pyb::object self) { return read_only(view(self.cast<PyProblem&>().p->lo, self)); },
                             "Lower bounds of λ (numpy view; friction rows: overwritten by −μ λ_n).")
      .def_property_readonly("hi", [](pyb::object self) { return read_only(view(self.cast<PyProblem&>().p->hi, self)); },
                             "Upper bounds of λ (numpy view; +inf on normal rows).")
      .def_property_readonly("mu", [](pyb::object self) { return read_only(view(self.cast<PyProblem&>().p->mu, self)); },
                             "Friction coefficient per row (0 on normal rows; numpy view).")
      .def_property_readonly("inv_mass",
                             [](pyb::object self) { return read_only(view(self.cast<PyProblem&>().p->inv_mass, self)); },
                             "M⁻¹ as a vector (1/m, 1/m, 1/I per body; numpy view; empty without J).")
      .def_property_readonly("normal_row",
                             [](const PyProblem& p) {
                               return pyb::array_t<int>(static_cast<pyb::ssize_t>(p.p->normal_row.size()),
                                                        p.p->normal_row.data());
                             },
                             "For each row, the row of the normal force bounding it (friction rows), or −1.")
      .def_property_readonly("dt", [](const PyProblem& p) { return p.p->dt; }, "The time step Δt of the problem [s].")
      .def_property_readonly("rows", [](const PyProblem& p) { return p.p->rows(); }, "Number of rows (unknowns λ).")
      .def("__len__", [](const PyProblem& p) { return p.p->rows(); }, "Number of rows.")
      .def("residual", [](const PyProblem& p, pyb::object lam) {
             return natural_residual(*p.p, to_vector_of_size(lam, "lam", p.p->rows()));
           },
           pyb::arg("lam"), "Natural-map residual max_i |λ_i − mid(lo_i, λ_i − w_i, hi_i)| [N].")
      .def("velocity", [](const PyProblem& p, pyb::object lam) { return copy(lcp_velocity(*p.p, to_vector_of_size(lam, "lam", p.p->rows()))); },
           pyb::arg("lam"), "w = A λ + b.")
      .def("__repr__", [](const PyProblem& p) {
        return "<deepcontact.Problem rows=" + std::to_string(p.p->rows()) +
               (p.p->has_jacobian() ? " (with J)" : "") + ">";
      });

  pyb::class_<PyResult>(m, "Result", "Outcome of a solve.")
      .def_property_readonly("lam", [](pyb::object self) { return view(self.cast<PyResult&>().r.lambda, self); },
                             "The returned λ (numpy view).")
      .def_property_readonly("status", [](const PyResult& r) { return std::string(to_string(r.r.status)); },
                             "converged | tolerance_reached | sweep_limit | diverged | infeasible | failed | invalid_input "
                             "(docs/lcp.md explains each).")
      .def_property_readonly("sweeps", [](const PyResult& r) { return r.r.sweeps; },
                             "Sweeps (or pivots / Newton iterations) performed.")
      .def_property_readonly("theta", [](pyb::object self) { return view(self.cast<PyResult&>().r.theta, self); },
                             "θ_k = max_i |λ_i^k − λ_i^(k−1)| per sweep [N] (empty unless recorded).")
      .def_property_readonly("residual", [](const PyResult& r) { return r.r.residual; },
                             "Natural-map residual at the returned λ [N].")
      .def_property_readonly("message", [](const PyResult& r) { return r.r.message; },
                             "Why a solve did not converge (empty when it did).")
      .def("__repr__", [](const PyResult& r) {
        return "<deepcontact.Result status=" + std::string(to_string(r.r.status)) +
               " sweeps=" + std::to_string(r.r.sweeps) + " residual=" + std::to_string(r.r.residual) + ">";
      });

  m.def(
      "solve",
      [](const PyProblem& problem, const std::string& solver, int sweeps, double tol, pyb::object lambda0,
         double omega, bool record_theta) {
        if (sweeps < 0) throw ConfigError("--sweeps must be >= 0");
        if (!(tol >= 0) || !std::isfinite(tol)) throw ConfigError("--tol must be finite and >= 0");
        const auto s = make_solver(solver);
        Eigen::VectorXd l0 =
            lambda0.is_none() ? Eigen::VectorXd() : to_vector_of_size(lambda0, "lambda0", problem.p->rows());
        if (!l0.allFinite()) throw pyb::value_error("lambda0: every entry must be finite");
        SolverOptions o;
        o.max_sweeps = sweeps;
        o.tolerance = tol;
        o.omega = omega;
        o.record_theta = record_theta;
        PyResult out;
        {
          pyb::gil_scoped_release release;
          out.r = s->solve(*problem.p, l0, o);
        }
        return out;
      },
      pyb::arg("problem"), pyb::arg("solver") = "pgs", pyb::arg("sweeps") = 3000, pyb::arg("tol") = 0.0,
      pyb::arg("lambda0") = pyb::none(), pyb::arg("omega") = 1.0, pyb::arg("record_theta") = true,
      "Solve the LCP with a solver of solvers() from lambda0 (None = zeros); the GIL is released meanwhile.");
  m.def("solvers", &solver_names, "Names of the LCP solvers solve() accepts.");
  m.def(
      "read_lcp_dat", [](pyb::object path) { return problem_to_python(read_lcp_dat(path_string(path))); },
      pyb::arg("path"), "A Siconos .dat LCP (dense or sparse-block storage) as a Problem (M = .A, q = .b).");
  m.def(
      "write_lcp_dat",
      [](pyb::object path, pyb::object M, pyb::object q) {
        const Eigen::MatrixXd dense(to_sparse(M, "M"));
        if (dense.rows() != dense.cols())
          throw pyb::value_error("M: expected a square matrix, got " + std::to_string(dense.rows()) + " x " +
                                 std::to_string(dense.cols()));
        write_lcp_dat(path_string(path), dense, to_vector_of_size(q, "q", dense.rows()));
      },
      pyb::arg("path"), pyb::arg("M"), pyb::arg("q"), "Write M, q as a Siconos .dat file (dense storage, %.17g).");
}

}  // namespace dc::py
