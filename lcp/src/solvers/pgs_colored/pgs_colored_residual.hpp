#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): the loops of the closing natural residual
// formed from J (pgs_colored_products.hpp), written against J's CSR arrays and the contacts with
// no per-entry iterator or bound lookup. They rebuild Jᵀλ and gather J·Δu row by row, so they
// cost several sweeps; the solve uses them only where the packed residual (residual/) cannot
// vouch for its Δu (a stopped sweep, a non-finite J or Δu⁰). Bit for bit the forms of
// lcp_problem.cpp:
//   (Jᵀλ)_c   = J_ic·λ_i added to 0 in ascending row order (Eigen's row-major scatter);
//   w_i       = Σ_q J_iq Δu_{c_q} in storage order, from 0, then + b_i;
//   error_i   = |λ_i − clamp(λ_i − w_i, l_i, max(l_i, h_i))| with the bounds of LcpProblem::lower
//               and upper: [lo_i, hi_i] for a normal row, ±μ_i·max(0, λ_n) for a tangent row.
// The residual is the maximum of the errors (order-free), +∞ when one is NaN.
#include <cstdint>
#include <cstring>

#include "dc/lcp/lcp_problem.hpp"

namespace dc::colored {

/// 1 when x is ±∞ or NaN (its exponent bits all set), else 0: integer ops, so that a loop OR-ing
/// it over many values vectorises (values_finite, velocity_change's check of Δu).
inline std::uint64_t not_finite_bit(double x) {
  constexpr std::uint64_t kExp = 0x7ff0000000000000ull;
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return static_cast<std::uint64_t>((bits & kExp) == kExp);
}

/// out[c] += J_ic·λ_i for rows i in [i0, i1) in ascending order, each row's entries in storage
/// order (the caller zeroes `out` first; columns outside [col0, col1) are skipped, for a thread
/// that owns a block of columns). skip_zero: rows with λ_i = ±0 are not read — the same bits
/// when every J entry is finite (values_finite): such a row adds ±0 to each of its columns' sums,
/// which start at +0 and so are never −0, and x + ±0 = x for every other x.
void transpose_rows(const LcpProblem& p, const double* lambda, int i0, int i1, int col0, int col1, double* out,
                    bool skip_zero = false);

/// transpose_rows over every row and column, from `out` as the caller left it (zeros), with
/// values_finite's test done chunk by chunk of rows on the entries it is about to scatter: a
/// chunk whose entries are all finite skips its rows with λ_i = ±0 (the same bits, above), any
/// other chunk scatters every row. So the sums are those of transpose_rows without the skip, bit
/// for bit, with one pass over J's values. Returns values_finite(p). With check = false the test
/// is left out (every chunk skips: the caller knows J is finite or discards `out` otherwise) and
/// true is returned.
bool transpose_rows_checked(const LcpProblem& p, const double* lambda, double* out, bool check = true);

/// True when every stored entry of J is finite (an OR over the exponent bits; for a J that is not
/// compressed, row by row). Allows transpose_rows's skip_zero.
bool values_finite(const LcpProblem& p);

/// The running maximum of the errors of contacts [c0, c1)'s rows into r (a NaN error sets `nan`
/// instead), with du = M⁻¹JᵀλΔt in column order; `nonfinite` is set when one of their λ_i is not
/// finite. Requires what the input checks verified: every row belongs to one contact, and a
/// tangent row's μ_i and normal row are its contact's. skip_rest (only when values_finite(p) and
/// every row acts on its contact's bodies only, as a successful packing checked): a contact whose
/// bodies' Δu entries are all ±0 has w_i = 0 + b_i exactly, its rows are not read.
void contact_errors(const LcpProblem& p, const double* lambda, const double* du, int c0, int c1, double& r, bool& nan,
                    bool& nonfinite, bool skip_rest = false);

/// The same for rows [i0, i1) one by one, with the bounds of LcpProblem::lower and upper (problems
/// whose rows are not all owned by contacts).
void row_errors(const LcpProblem& p, const Eigen::VectorXd& lambda, const double* du, int i0, int i1, double& r, bool& nan,
                bool& nonfinite);

}  // namespace dc::colored
