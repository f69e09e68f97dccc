// The loops of pgs-colored's closing natural residual (pgs_colored_residual.hpp).
#include "solvers/pgs_colored/pgs_colored_residual.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace dc::colored {
namespace {

/// First and one-past-last storage index of row i of a row-major J (compressed or not).
inline void row_extent(const int* outer, const int* nnz, int i, int& q0, int& q1) {
  q0 = outer[i];
  q1 = nnz != nullptr ? q0 + nnz[i] : outer[i + 1];
}

/// w_i = Σ_q J_iq du_{c_q} in storage order from 0, then + b_i.
inline double row_w(const double* value, const int* inner, int q0, int q1, const double* du, double b) {
  double tmp = 0.0;
  for (int q = q0; q < q1; ++q) tmp += value[q] * du[inner[q]];
  return tmp + b;
}

/// |λ − clamp(λ − w, l, max(l, h))| as lcp_problem.cpp's natural residual writes it.
inline double row_error(double x, double w, double l, double h) {
  return std::abs(x - std::clamp(x - w, l, std::max(l, h)));
}

inline void fold(double e, double& r, bool& nan) {
  if (std::isnan(e)) {
    nan = true;
  } else {
    r = std::max(r, e);
  }
}

/// out[c] += J_ic·l for row i's entries in storage order (columns outside [col0, col1) skipped
/// unless `all`).
inline void scatter_row(const double* value, const int* inner, const int* outer, const int* nnz, int i, double l,
                        bool all, int col0, int col1, double* out) {
  int q0 = 0, q1 = 0;
  row_extent(outer, nnz, i, q0, q1);
  if (all) {
    for (int q = q0; q < q1; ++q) out[inner[q]] += value[q] * l;
  } else {
    for (int q = q0; q < q1; ++q) {
      const int c = inner[q];
      if (c >= col0 && c < col1) out[c] += value[q] * l;
    }
  }
}

/// No entry of x[0..n) is ±∞ or NaN (integer ops on the exponent bits: the compiler vectorises).
bool finite_run(const double* x, int n) {
  std::uint64_t any = 0;
  for (int i = 0; i < n; ++i) any |= not_finite_bit(x[i]);
  return any == 0;
}

/// Rows per chunk of transpose_rows's lists.
constexpr int kChunk = 256;

/// rows[0..m) ← the rows k of [i, end) with λ_k ≠ 0 (NaN included), in order; returns m. No
/// branch per row (which of a pile's rows are 0 follows no pattern a predictor learns).
inline int list_nonzero(const double* lambda, int i, int end, int* rows) {
  int m = 0;
  for (int k = i; k < end; ++k) {
    rows[m] = k;
    m += lambda[k] != 0.0 ? 1 : 0;
  }
  return m;
}

/// out[c] += J_ic·λ_i for the listed rows rows[0..m) in order, every column.
inline void scatter_listed(const double* value, const int* inner, const int* outer, const int* nnz, const int* rows,
                           int m, const double* lambda, double* out) {
  for (int j = 0; j < m; ++j) {
    int q0 = 0, q1 = 0;
    row_extent(outer, nnz, rows[j], q0, q1);
    const double l = lambda[rows[j]];
    for (int q = q0; q < q1; ++q) out[inner[q]] += value[q] * l;
  }
}

/// Δu of body k's three columns all ±0 (a body with no column, k < 0, counts as at rest).
inline bool at_rest(const double* du, int k) {
  if (k < 0) return true;
  const double* u = du + 3 * k;
  return (u[0] == 0.0) & (u[1] == 0.0) & (u[2] == 0.0);
}

}  // namespace

void transpose_rows(const LcpProblem& p, const double* lambda, int i0, int i1, int col0, int col1, double* out,
                    bool skip_zero) {
  const double* value = p.J.valuePtr();
  const int* inner = p.J.innerIndexPtr();
  const int* outer = p.J.outerIndexPtr();
  const int* nnz = p.J.innerNonZeroPtr();  // null when compressed
  const bool all = col0 <= 0 && col1 >= p.J.cols();
  if (!skip_zero) {
    for (int i = i0; i < i1; ++i) scatter_row(value, inner, outer, nnz, i, lambda[i], all, col0, col1, out);
    return;
  }
  // The rows with λ_i ≠ 0 (NaN included) of each chunk listed first, without a branch per row
  // (which of a pile's rows are 0 follows no pattern a predictor learns), then scattered in order.
  int rows[kChunk];
  for (int i = i0; i < i1; i += kChunk) {
    const int end = std::min(i1, i + kChunk);
    const int m = list_nonzero(lambda, i, end, rows);
    if (all) {
      scatter_listed(value, inner, outer, nnz, rows, m, lambda, out);
    } else {
      for (int j = 0; j < m; ++j)
        scatter_row(value, inner, outer, nnz, rows[j], lambda[rows[j]], all, col0, col1, out);
    }
  }
}

bool transpose_rows_checked(const LcpProblem& p, const double* lambda, double* out, bool check) {
  const double* value = p.J.valuePtr();
  const int* inner = p.J.innerIndexPtr();
  const int* outer = p.J.outerIndexPtr();
  const int* nnz = p.J.innerNonZeroPtr();  // null when compressed
  const int n = p.rows();
  bool finite = true;
  int rows[kChunk];
  for (int i = 0; i < n; i += kChunk) {
    const int end = std::min(n, i + kChunk);
    // values_finite's test on this chunk's entries (they are read again at once, from cache)
    bool chunk_finite = true;
    if (check && nnz == nullptr) {
      chunk_finite = finite_run(value + outer[i], outer[end] - outer[i]);
    } else if (check) {
      for (int k = i; k < end; ++k) chunk_finite &= finite_run(value + outer[k], nnz[k]);
    }
    finite = finite && chunk_finite;
    int m = 0;
    if (chunk_finite) {
      m = list_nonzero(lambda, i, end, rows);
    } else {  // a non-finite entry: every row of the chunk, as the product without the skip
      for (int k = i; k < end; ++k) rows[m++] = k;
    }
    scatter_listed(value, inner, outer, nnz, rows, m, lambda, out);
  }
  return finite;
}

bool values_finite(const LcpProblem& p) {
  const double* value = p.J.valuePtr();
  if (p.J.isCompressed()) return finite_run(value, static_cast<int>(p.J.nonZeros()));
  const int* outer = p.J.outerIndexPtr();
  const int* nnz = p.J.innerNonZeroPtr();
  bool ok = true;
  for (int i = 0; i < p.J.rows(); ++i) ok &= finite_run(value + outer[i], nnz[i]);
  return ok;
}

void contact_errors(const LcpProblem& p, const double* lambda, const double* du, int c0, int c1, double& r_io,
                    bool& nan_io, bool& nonfinite, bool skip_rest) {
  double r = r_io;  // (locals: a store through the references would be reloaded every row)
  bool nan = nan_io;
  const double* value = p.J.valuePtr();
  const int* inner = p.J.innerIndexPtr();
  const int* outer = p.J.outerIndexPtr();
  const int* nnz = p.J.innerNonZeroPtr();
  const double* b = p.b.data();
  const double* lo = p.lo.data();
  const double* hi = p.hi.data();
  const ContactConstraint* cons = p.constraints.contacts().data();
  bool bad = false;
  for (int c = c0; c < c1; ++c) {
    const ContactConstraint& k = cons[c];
    // Both bodies at rest in Δu: each row's sum is 0 + J_iq·(±0) + … = +0 (J finite), so
    // w_i = 0 + b_i without reading the row.
    const bool rest = skip_rest && at_rest(du, k.body_a) && at_rest(du, k.body_b);
    const int n = k.normal_row;
    int q0 = 0, q1 = 0;
    row_extent(outer, nnz, n, q0, q1);
    const double xn = lambda[n];
    bad = bad || !std::isfinite(xn);
    const double wn = rest ? 0.0 + b[n] : row_w(value, inner, q0, q1, du, b[n]);
    fold(row_error(xn, wn, lo[n], hi[n]), r, nan);
    if (k.tangent_row < 0) continue;
    const int t = k.tangent_row;
    const double xt = lambda[t];
    const double bound = std::max(0.0, xn);
    double wt = 0.0 + b[t];
    if (!rest) {
      int p0 = 0, p1 = 0;
      row_extent(outer, nnz, t, p0, p1);
      wt = row_w(value, inner, p0, p1, du, b[t]);
    }
    fold(row_error(xt, wt, -k.mu * bound, k.mu * bound), r, nan);
    bad = bad || !std::isfinite(xt);
  }
  nonfinite = nonfinite || bad;
  r_io = r;
  nan_io = nan;
}

void row_errors(const LcpProblem& p, const Eigen::VectorXd& lambda, const double* du, int i0, int i1, double& r_io,
                bool& nan_io, bool& nonfinite) {
  double r = r_io;
  bool nan = nan_io;
  const double* value = p.J.valuePtr();
  const int* inner = p.J.innerIndexPtr();
  const int* outer = p.J.outerIndexPtr();
  const int* nnz = p.J.innerNonZeroPtr();
  bool bad = false;
  for (int i = i0; i < i1; ++i) {
    int q0 = 0, q1 = 0;
    row_extent(outer, nnz, i, q0, q1);
    bad = bad || !std::isfinite(lambda[i]);
    fold(row_error(lambda[i], row_w(value, inner, q0, q1, du, p.b[i]), p.lower(i, lambda), p.upper(i, lambda)), r, nan);
  }
  nonfinite = nonfinite || bad;
  r_io = r;
  nan_io = nan;
}

}  // namespace dc::colored
