// deepcontact._core: the pybind11 extension behind the `deepcontact` Python package
// (python/deepcontact/__init__.py; docs/python.md). The GIL is released while C++ runs and
// taken again for every call into a warm starter written in Python.
#include "dc/core/install_paths.hpp"
#include "dc/io/h5.hpp"
#include "py_common.hpp"

namespace {

/// PEP 440 version with the commit as local label: "0.1.0+g1a2b3c4d5e6f" ("….dirty" when the
/// build's work tree had changes, "0.1.0+unknown" outside git).
std::string python_version() {
  std::string commit = dc::git_commit();
  if (commit == "unknown") return dc::version() + "+unknown";
  if (const auto dash = commit.find('-'); dash != std::string::npos) commit.replace(dash, 1, ".");
  return dc::version() + "+g" + commit;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  // First, as in the CLI's main: libhdf5's exit-time cleanup crashes after a failed write
  // (h5.hpp). Files of h5py in the same process are then not closed for it at exit: close them.
  dc::h5_skip_exit_cleanup();
  m.doc() = "DeepContact engine, LCP solvers, warm starters and bench (C++ core)";
  m.attr("__version__") = python_version();
  m.attr("__commit__") = dc::git_commit();
  dc::py::bind_errors(m);
  dc::py::bind_problem(m);
  dc::py::bind_problem_file(m);
  dc::py::bind_world(m);
  dc::py::bind_bench(m);
  dc::py::bind_io(m);
}
