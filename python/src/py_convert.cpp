// numpy / scipy.sparse conversions of the module (py_common.hpp).
#include <pybind11/eigen.h>

#include <limits>

#include "dc/core/error.hpp"
#include "py_common.hpp"

namespace dc::py {

pyb::array_t<double> view(const double* data, std::size_t n, pyb::handle base) {
  const auto size = static_cast<pyb::ssize_t>(n);
  if (base.is_none()) return pyb::array_t<double>(size, data);  // no base: numpy copies
  return pyb::array_t<double>({size}, {static_cast<pyb::ssize_t>(sizeof(double))}, data, base);
}

pyb::array_t<double> view(const std::vector<Vec2>& v, pyb::handle base) {
  static_assert(sizeof(Vec2) == 2 * sizeof(double), "Vec2 must be two packed doubles");
  const auto n = static_cast<pyb::ssize_t>(v.size());
  const double* data = v.empty() ? nullptr : &v.front().x;
  std::vector<pyb::ssize_t> shape{n, 2}, strides{static_cast<pyb::ssize_t>(sizeof(Vec2)),
                                                 static_cast<pyb::ssize_t>(sizeof(double))};
  if (base.is_none() || v.empty()) return pyb::array_t<double>(shape, strides, data);
  return pyb::array_t<double>(shape, strides, data, base);
}

pyb::array_t<double> view(const std::vector<double>& v, pyb::handle base) {
  return view(v.data(), v.size(), v.empty() ? pyb::none() : base);
}

pyb::array_t<double> view(const Eigen::Ref<const Eigen::VectorXd>& v, pyb::handle base) {
  return view(v.data(), static_cast<std::size_t>(v.size()), v.size() == 0 ? pyb::none() : base);
}

pyb::array_t<double> copy(const Eigen::Ref<const Eigen::VectorXd>& v) { return view(v, pyb::none()); }

pyb::array read_only(pyb::array a) {
  a.attr("setflags")(pyb::arg("write") = false);
  return a;
}

void require_real_numbers(pyb::handle obj, const std::string& what) {
  auto np = pyb::module_::import("numpy");
  pyb::object dtype;
  if (pyb::module_::import("scipy.sparse").attr("issparse")(obj).cast<bool>()) dtype = obj.attr("dtype");
  else if (pyb::hasattr(obj, "dtype")) dtype = obj.attr("dtype");
  else dtype = np.attr("asarray")(obj).attr("dtype");
  // b boolean, i/u integers, f floating: exact in float64 or rounded; c complex would lose
  // its imaginary part, O/U/S/V (objects, text, records) are no numbers.
  const std::string kind = pyb::str(np.attr("dtype")(dtype).attr("kind"));
  if (kind != "b" && kind != "i" && kind != "u" && kind != "f")
    throw pyb::type_error(what + ": expected real numbers, got an array of dtype " +
                          pyb::str(dtype).cast<std::string>() + (kind == "c" ? " (complex)" : ""));
}

Eigen::VectorXd to_vector(pyb::handle obj, const std::string& what) {
  require_real_numbers(obj, what);
  auto a = pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(obj);
  if (!a) throw pyb::value_error(what + ": expected an array of numbers");
  if (a.ndim() != 1) throw pyb::value_error(what + ": expected a 1-D array, got " + std::to_string(a.ndim()) + "-D");
  Eigen::VectorXd v(a.shape(0));
  std::copy(a.data(), a.data() + a.shape(0), v.data());
  return v;
}

pyb::object csr_view(const SparseRowMatrix& m, pyb::handle base) {
  if (!m.isCompressed()) throw InvalidArgument("csr_view: matrix is not compressed");
  const auto rows = static_cast<pyb::ssize_t>(m.rows()), nnz = static_cast<pyb::ssize_t>(m.nonZeros());
  // Read-only: an index written through a view (indices[0] = 10**6) would send the solvers
  // outside the matrix, and the problem is checked only when it is made.
  pyb::array indptr = read_only(
      pyb::array_t<int>({rows + 1}, {static_cast<pyb::ssize_t>(sizeof(int))}, m.outerIndexPtr(), base));
  pyb::array indices =
      read_only(pyb::array_t<int>({nnz}, {static_cast<pyb::ssize_t>(sizeof(int))}, m.innerIndexPtr(), base));
  pyb::array data =
      read_only(pyb::array_t<double>({nnz}, {static_cast<pyb::ssize_t>(sizeof(double))}, m.valuePtr(), base));
  auto csr = pyb::module_::import("scipy.sparse").attr("csr_matrix");
  return csr(pyb::make_tuple(data, indices, indptr), pyb::arg("shape") = pyb::make_tuple(m.rows(), m.cols()),
             pyb::arg("copy") = false);
}

namespace {

/// ValueError naming `what` unless indptr, indices and data form a CSR matrix of rows × cols:
/// sizes that fit an int, rows + 1 non-decreasing row pointers from 0 to nnz, column indices
/// in [0, cols), one value per index.
void require_valid_csr(const std::string& what, long rows, long cols, const pyb::array_t<long long>& indptr,
                       const pyb::array_t<long long>& indices, const pyb::array_t<double>& data) {
  constexpr long kMax = std::numeric_limits<int>::max();
  if (rows < 0 || cols < 0 || rows > kMax || cols > kMax)
    throw pyb::value_error(what + ": shape (" + std::to_string(rows) + ", " + std::to_string(cols) +
                           ") is negative or too large");
  if (indptr.ndim() != 1 || indices.ndim() != 1 || data.ndim() != 1 || indptr.shape(0) != rows + 1)
    throw pyb::value_error(what + ": indptr must have rows + 1 = " + std::to_string(rows + 1) + " entries, got " +
                           std::to_string(indptr.size()));
  const auto nnz = static_cast<long long>(indices.shape(0));
  if (data.shape(0) != indices.shape(0) || nnz > kMax)
    throw pyb::value_error(what + ": " + std::to_string(data.shape(0)) + " values for " + std::to_string(nnz) +
                           " column indices");
  const long long* p = indptr.data();
  if (p[0] != 0 || p[rows] != nnz)
    throw pyb::value_error(what + ": indptr must run from 0 to the number of stored values " + std::to_string(nnz));
  for (long r = 0; r < rows; ++r)
    if (p[r + 1] < p[r]) throw pyb::value_error(what + ": indptr decreases at row " + std::to_string(r));
  const long long* col = indices.data();
  for (long long k = 0; k < nnz; ++k)
    if (col[k] < 0 || col[k] >= cols)
      throw pyb::value_error(what + ": column index " + std::to_string(col[k]) + " (stored value " +
                             std::to_string(k) + ") is outside [0, " + std::to_string(cols) + ")");
}

}  // namespace

Eigen::VectorXd to_vector_of_size(pyb::handle obj, const std::string& what, Eigen::Index n) {
  Eigen::VectorXd v = to_vector(obj, what);
  if (v.size() != n)
    throw pyb::value_error(what + ": expected " + std::to_string(n) + " entries, got " + std::to_string(v.size()));
  return v;
}

SparseRowMatrix to_sparse(pyb::handle obj, const std::string& what) {
  require_real_numbers(obj, what);
  auto sp = pyb::module_::import("scipy.sparse");
  pyb::object csr;
  if (sp.attr("issparse")(obj).cast<bool>()) {
    csr = sp.attr("csr_matrix")(obj);
  } else {
    auto np = pyb::module_::import("numpy");
    pyb::object dense = np.attr("asarray")(obj, pyb::arg("dtype") = np.attr("float64"));
    if (dense.attr("ndim").cast<int>() != 2) throw pyb::value_error(what + ": expected a 2-D matrix");
    csr = sp.attr("csr_matrix")(dense);
  }
  const auto shape = csr.attr("shape").cast<std::pair<long, long>>();
  auto indptr = pyb::array_t<long long, pyb::array::c_style | pyb::array::forcecast>::ensure(csr.attr("indptr"));
  auto indices = pyb::array_t<long long, pyb::array::c_style | pyb::array::forcecast>::ensure(csr.attr("indices"));
  auto data = pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(csr.attr("data"));
  // scipy builds a csr_matrix from (data, indices, indptr) without checking the indices, and
  // Eigen's setFromTriplets writes wherever an index points: check everything first.
  require_valid_csr(what, shape.first, shape.second, indptr, indices, data);
  SparseRowMatrix m(shape.first, shape.second);
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(static_cast<std::size_t>(data.size()));
  for (long r = 0; r < shape.first; ++r)
    for (long long k = indptr.at(r); k < indptr.at(r + 1); ++k)
      t.emplace_back(static_cast<int>(r), static_cast<int>(indices.at(k)), data.at(k));
  m.setFromTriplets(t.begin(), t.end());
  m.makeCompressed();
  return m;
}

std::string path_string(pyb::handle path) {
  // os.fspath also passes bytes, which str() would turn into "b'…'"; a NUL would end the
  // path early in the C library (x.dat\0junk opens x.dat).
  pyb::object p;
  try {
    p = pyb::module_::import("os").attr("fspath")(path);
  } catch (const pyb::error_already_set& e) {
    if (!e.matches(PyExc_TypeError)) throw;
    p = pyb::none();
  }
  if (!pyb::isinstance<pyb::str>(p))
    throw pyb::type_error("a path must be a str or os.PathLike giving a str, got " +
                          pyb::str(pyb::type::of(path).attr("__name__")).cast<std::string>());
  std::string s = p.cast<std::string>();
  if (s.find('\0') != std::string::npos) throw pyb::value_error("a path must not contain a NUL character");
  if (s.empty()) throw pyb::value_error("a path must not be empty");
  return s;
}

pyb::object make_fields() {
  // deepcontact/__init__.py defines Fields before it is usable; cached after the first call.
  static pyb::handle cls = pyb::object(pyb::module_::import("deepcontact").attr("Fields")).release();
  return cls();
}

}  // namespace dc::py
