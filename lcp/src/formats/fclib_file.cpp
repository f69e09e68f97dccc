#include "dc/lcp/fclib_file.hpp"

#include <cmath>
#include <string>

#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"

namespace dc {
namespace {

constexpr const char* kW = "/fclib_local/W/";

/// One int32 stored as a dataset of shape (1) (libfclib's way) or a scalar.
/// IoError unless `path` is a dataset whose values are in this file (no virtual dataset, no
/// external link or storage: HDF5 reads a missing source as zeros).
void require_dataset(const H5File& f, const std::string& path) {
  f.require_in_file(path);
  if (!f.is_dataset(path)) throw IoError(f.path() + ": " + path + " is missing");
}

std::int64_t scalar_int(const H5File& f, const std::string& path) {
  require_dataset(f, path);
  const H5Shape s = f.shape(path);
  if (!(s.empty() || (s.size() == 1 && s[0] == 1)))
    throw IoError(f.path() + ": " + path + " has shape " + to_string(s) + ", expected one number");
  return f.read<std::int64_t>(path)[0];
}

template <H5Element T>
std::vector<T> vector_of(const H5File& f, const std::string& path, std::int64_t count) {
  require_dataset(f, path);
  f.require_shape(path, {static_cast<hsize_t>(count)});
  return f.read<T>(path);
}

/// Checks a compressed layout (starts of `outer` lists of indices below `inner`): starts from
/// 0, non-decreasing, ending at the entry count; indices in range; none twice in one list.
void check_compressed(const std::vector<std::int32_t>& start, const std::vector<std::int32_t>& index,
                      std::int64_t inner, const std::string& where) {
  if (start.empty() || start[0] != 0) throw IoError(where + ": the first pointer must be 0");
  std::vector<std::int64_t> seen(static_cast<size_t>(inner), -1);
  for (size_t j = 0; j + 1 < start.size(); ++j) {
    if (start[j + 1] < start[j] || start[j + 1] > static_cast<std::int64_t>(index.size()))
      throw IoError(where + ": pointer " + std::to_string(j + 1) + " = " + std::to_string(start[j + 1]) +
                    " is out of order or beyond the " + std::to_string(index.size()) + " entries");
    for (std::int32_t k = start[j]; k < start[j + 1]; ++k) {
      const std::int32_t i = index[static_cast<size_t>(k)];
      if (i < 0 || i >= inner)
        throw IoError(where + ": index " + std::to_string(i) + " of entry " + std::to_string(k) + " is out of range");
      if (seen[static_cast<size_t>(i)] == static_cast<std::int64_t>(j))
        throw IoError(where + ": entry (" + std::to_string(j) + ", " + std::to_string(i) + ") is given twice");
      seen[static_cast<size_t>(i)] = static_cast<std::int64_t>(j);
    }
  }
}

void check_finite(const std::vector<double>& v, const std::string& where) {
  for (size_t k = 0; k < v.size(); ++k)
    if (!std::isfinite(v[k])) throw IoError(where + ": entry " + std::to_string(k) + " is not finite");
}

/// Transposes a compressed layout (rows ↔ columns) with a counting sort.
void transpose(std::int64_t n, std::vector<std::int32_t>& start, std::vector<std::int32_t>& index,
               std::vector<double>& x) {
  const size_t nnz = static_cast<size_t>(start[static_cast<size_t>(n)]);
  std::vector<std::int32_t> ts(static_cast<size_t>(n) + 1, 0), ti(nnz);
  std::vector<double> tx(nnz);
  for (size_t k = 0; k < nnz; ++k) ++ts[static_cast<size_t>(index[k]) + 1];
  for (std::int64_t j = 0; j < n; ++j) ts[static_cast<size_t>(j) + 1] += ts[static_cast<size_t>(j)];
  std::vector<std::int32_t> next(ts.begin(), ts.end() - 1);
  for (std::int64_t j = 0; j < n; ++j)
    for (std::int32_t k = start[static_cast<size_t>(j)]; k < start[static_cast<size_t>(j) + 1]; ++k) {
      const std::int32_t slot = next[static_cast<size_t>(index[static_cast<size_t>(k)])]++;
      ti[static_cast<size_t>(slot)] = static_cast<std::int32_t>(j);
      tx[static_cast<size_t>(slot)] = x[static_cast<size_t>(k)];
    }
  start = std::move(ts);
  index = std::move(ti);
  x = std::move(tx);
}

/// W as compressed columns, whatever layout the file used.
void read_matrix(const H5File& f, FclibLocalProblem& p) {
  const std::string& name = f.path();
  const std::int64_t m = scalar_int(f, std::string(kW) + "m"), n = scalar_int(f, std::string(kW) + "n");
  const std::int64_t nz = scalar_int(f, std::string(kW) + "nz"), nzmax = scalar_int(f, std::string(kW) + "nzmax");
  if (m != n) throw IoError(name + ": W is " + std::to_string(m) + "x" + std::to_string(n) + ", not square");
  if (m < 2 || m > kMaxFclibRows || m % 2 != 0)
    throw IoError(name + ": W has " + std::to_string(m) + " rows; 2 per contact, 2 … " +
                  std::to_string(kMaxFclibRows) + " expected");
  if (nz < -2 || nzmax < 0 || nzmax > kMaxFclibEntries || nz > kMaxFclibEntries ||
      static_cast<double>(nzmax) > static_cast<double>(m) * static_cast<double>(m))
    throw IoError(name + ": W/nz = " + std::to_string(nz) + ", W/nzmax = " + std::to_string(nzmax) + " are impossible");
  p.rows = static_cast<int>(m);
  if (nz < 0) {  // compressed columns (−1) or rows (−2)
    p.col_start = vector_of<std::int32_t>(f, std::string(kW) + "p", m + 1);
    p.row_index = vector_of<std::int32_t>(f, std::string(kW) + "i", nzmax);
    p.values = vector_of<double>(f, std::string(kW) + "x", nzmax);
    check_compressed(p.col_start, p.row_index, m, name + ": " + kW + (nz == -1 ? "p (columns)" : "p (rows)"));
    const size_t used = static_cast<size_t>(p.col_start.back());
    p.row_index.resize(used);
    p.values.resize(used);
    if (nz == -2) transpose(m, p.col_start, p.row_index, p.values);
  } else {  // triplet list: i = row, p = column of each entry
    const std::vector<std::int32_t> col = vector_of<std::int32_t>(f, std::string(kW) + "p", nz);
    const std::vector<std::int32_t> row = vector_of<std::int32_t>(f, std::string(kW) + "i", nz);
    const std::vector<double> x = vector_of<double>(f, std::string(kW) + "x", nz);
    std::vector<std::int32_t> by_col(static_cast<size_t>(m) + 1, 0);
    for (std::int64_t k = 0; k < nz; ++k) {
      if (col[static_cast<size_t>(k)] < 0 || col[static_cast<size_t>(k)] >= m)
        throw IoError(name + ": triplet " + std::to_string(k) + " has column " + std::to_string(col[static_cast<size_t>(k)]) +
                      " out of range");
      ++by_col[static_cast<size_t>(col[static_cast<size_t>(k)]) + 1];
    }
    for (std::int64_t j = 0; j < m; ++j) by_col[static_cast<size_t>(j) + 1] += by_col[static_cast<size_t>(j)];
    p.col_start = by_col;
    p.row_index.assign(static_cast<size_t>(nz), 0);
    p.values.assign(static_cast<size_t>(nz), 0.0);
    for (std::int64_t k = 0; k < nz; ++k) {
      const std::int32_t slot = by_col[static_cast<size_t>(col[static_cast<size_t>(k)])]++;
      p.row_index[static_cast<size_t>(slot)] = row[static_cast<size_t>(k)];
      p.values[static_cast<size_t>(slot)] = x[static_cast<size_t>(k)];
    }
    check_compressed(p.col_start, p.row_index, m, name + ": " + kW + "i (triplet rows)");
  }
  check_finite(p.values, name + ": " + kW + "x");
}

FclibSolution read_solution(const H5File& f, const std::string& group, std::int64_t rows) {
  FclibSolution s;
  s.r = vector_of<double>(f, group + "/r", rows);
  s.u = vector_of<double>(f, group + "/u", rows);
  check_finite(s.r, f.path() + ": " + group + "/r");
  check_finite(s.u, f.path() + ": " + group + "/u");
  return s;
}

/// The reader's checks on a problem in memory (the writer's precondition).
void check_problem(const FclibLocalProblem& p, const std::string& where) {
  if (p.rows < 2 || p.rows % 2 != 0 || p.rows > kMaxFclibRows)
    throw InvalidArgument(where + ": W must have 2 rows per contact, got " + std::to_string(p.rows));
  if (p.col_start.size() != static_cast<size_t>(p.rows) + 1 || p.row_index.size() != p.values.size() ||
      static_cast<size_t>(p.col_start.back()) != p.values.size())
    throw InvalidArgument(where + ": W's compressed columns are inconsistent");
  if (p.q.size() != static_cast<size_t>(p.rows) || p.mu.size() != static_cast<size_t>(p.rows / 2))
    throw InvalidArgument(where + ": q must have 2nc and mu nc entries");
  try {
    check_compressed(p.col_start, p.row_index, p.rows, where + ": W");
    check_finite(p.values, where + ": W");
    check_finite(p.q, where + ": q");
    check_finite(p.mu, where + ": mu");
  } catch (const IoError& e) {
    throw InvalidArgument(e.what());
  }
  for (double m : p.mu)
    if (m < 0) throw InvalidArgument(where + ": a friction coefficient is negative");
  auto check_sol = [&](const FclibSolution& s) {
    if (s.r.size() != static_cast<size_t>(p.rows) || s.u.size() != static_cast<size_t>(p.rows))
      throw InvalidArgument(where + ": a solution or guess must have r and u of 2nc entries");
    try {  // the reader refuses non-finite values: write none
      check_finite(s.r, where + ": a solution or guess's r");
      check_finite(s.u, where + ": a solution or guess's u");
    } catch (const IoError& e) {
      throw InvalidArgument(e.what());
    }
  };
  if (p.solution) check_sol(*p.solution);
  for (const FclibSolution& g : p.guesses) check_sol(g);
}

}  // namespace

FclibLocalProblem read_fclib_local(const std::string& path) {
  const H5File f = H5File::open_read(path);
  if (!f.is_group("/fclib_local")) {
    if (f.exists("/fclib_global") || f.exists("/fclib_global_rolling"))
      throw IoError(path + ": a global FCLIB problem: only local problems (/fclib_local) are read");
    throw IoError(path + ": no /fclib_local group: not an FCLIB local problem");
  }
  const std::int64_t dim = scalar_int(f, "/fclib_local/spacedim");
  if (dim == 3) throw IoError(path + ": spacedim 3 (3D friction) is not supported: only 2D problems");
  if (dim != 2) throw IoError(path + ": spacedim " + std::to_string(dim) + " is not 2");
  if (f.exists("/fclib_local/V") || f.exists("/fclib_local/R"))
    throw IoError(path + ": /fclib_local has V and R (a mixed problem with equality constraints): not supported");
  FclibLocalProblem p;
  read_matrix(f, p);
  p.q = vector_of<double>(f, "/fclib_local/vectors/q", p.rows);
  p.mu = vector_of<double>(f, "/fclib_local/vectors/mu", p.rows / 2);
  check_finite(p.q, path + ": /fclib_local/vectors/q");
  check_finite(p.mu, path + ": /fclib_local/vectors/mu");
  for (size_t c = 0; c < p.mu.size(); ++c)
    if (p.mu[c] < 0) throw IoError(path + ": mu of contact " + std::to_string(c) + " is negative");
  if (f.is_group("/solution")) p.solution = read_solution(f, "/solution", p.rows);
  if (f.is_group("/guesses")) {
    const std::int64_t count = scalar_int(f, "/guesses/number_of_guesses");
    if (count < 0 || count > 10000)
      throw IoError(path + ": /guesses/number_of_guesses = " + std::to_string(count) + " is out of range 0 … 10000");
    for (std::int64_t g = 1; g <= count; ++g) p.guesses.push_back(read_solution(f, "/guesses/" + std::to_string(g), p.rows));
  }
  return p;
}

void write_fclib_local(const std::string& path, const FclibLocalProblem& p) {
  check_problem(p, path);
  AtomicH5File out(path);
  const auto n = static_cast<hsize_t>(p.rows);
  const auto nnz = static_cast<std::int32_t>(p.values.size());
  auto one = [&](const std::string& name, std::int32_t v) { out->write<std::int32_t>(name, std::vector<std::int32_t>{v}, {1}); };
  one("/fclib_local/spacedim", 2);
  one(std::string(kW) + "nzmax", nnz);
  one(std::string(kW) + "m", p.rows);
  one(std::string(kW) + "n", p.rows);
  one(std::string(kW) + "nz", -1);  // compressed columns
  out->write<std::int32_t>(std::string(kW) + "p", p.col_start, {n + 1});
  out->write<std::int32_t>(std::string(kW) + "i", p.row_index, {static_cast<hsize_t>(nnz)});
  out->write<double>(std::string(kW) + "x", p.values, {static_cast<hsize_t>(nnz)});
  out->write<double>("/fclib_local/vectors/q", p.q, {n});
  out->write<double>("/fclib_local/vectors/mu", p.mu, {n / 2});
  auto solution = [&](const std::string& group, const FclibSolution& s) {
    out->write<double>(group + "/u", s.u, {n});
    out->write<double>(group + "/r", s.r, {n});
  };
  if (p.solution) solution("/solution", *p.solution);
  if (!p.guesses.empty()) {
    one("/guesses/number_of_guesses", static_cast<std::int32_t>(p.guesses.size()));
    for (size_t g = 0; g < p.guesses.size(); ++g) solution("/guesses/" + std::to_string(g + 1), p.guesses[g]);
  }
  out.commit();
}

}  // namespace dc
