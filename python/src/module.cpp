// deepcontact._core: the pybind11 extension behind the `deepcontact` Python package
// (python/deepcontact/__init__.py; docs/python.md). The GIL is released while C++ runs and
// taken again for every call into a warm starter written in Python.
#include "py_common.hpp"

PYBIND11_MODULE(_core, m) {
  m.doc() = "DeepContact engine, LCP solvers, warm starters and bench (C++ core)";
  dc::py::bind_errors(m);
  dc::py::bind_problem(m);
  dc::py::bind_world(m);
  dc::py::bind_bench(m);
  dc::py::bind_io(m);
}
