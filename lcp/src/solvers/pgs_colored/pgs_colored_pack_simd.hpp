#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): the packing of one row of each of the W
// lanes of a batch at once (pgs_colored_layout.cpp's fill_batch), 4 lanes per AVX2 register:
// each lane's J entries and M⁻¹ entries are loaded as rows and brought into slot order by 4 × 4
// transposes, and the per-lane arithmetic of pack_row and scale_rows follows in their order
// (r = 0 + J_is, m = r·M⁻¹·Δt, A_ii = Σ r·m in slot order, then j = r·(1/A_ii), b = b_i·(1/A_ii)),
// so the packed batch is the scalar packing's bit for bit.
#include <cstdint>

#include "dc/lcp/lcp_problem.hpp"
#include "solvers/pgs_colored/compact/compact_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"

namespace dc::colored {

/// The rows rows[0..W) of J on the bodies at J columns a[k] (slots 0–2) and bb[k] (slots 3–5;
/// −1: none), when every row has the usual storage (pack_row's: the columns a, a+1, a+2 (, bb,
/// bb+1, bb+2) once each, in order): writes j = J_i/A_ii and mj = M⁻¹J_iᵀΔt (zeros in absent
/// slots), b = b_i/A_ii, diag = A_ii, and returns the lanes whose A_ii is not finite and > 0 or 1/A_ii not
/// finite as a bit mask in `singular`. Returns false, writing nothing, when a row's storage is
/// not the usual one (the caller packs the batch lane by lane then) or when this build or CPU
/// has no AVX2 (simd_pack_available).
bool pack_rows_simd(const LcpProblem& p, const int* rows, const int* a, const int* bb, double (*j)[W],
                    double (*mj)[W], double* b, double* diag, unsigned& singular);

/// pack_rows_simd on rows given by their entries: lane k's 6 J entries at base + off[k] (slots
/// 3–5 +0 when bb[k] < 0) and b_i in bi[k]; the same bits. False without AVX2.
bool pack_rows_staged(const double* base, const int* off, const double* bi, const int* a, const int* bb,
                      const double* im, double dt, double (*j)[W], double (*mj)[W], double* b, double* diag,
                      unsigned& singular);

/// The normal rows rn[0..W) and tangent rows rt[0..W) of W single contacts with friction (bodies
/// as pack_rows_simd's) packed straight into C's rows, not its bodies or count: the coefficients
/// pack_rows_simd and over_relax by ω (≠ 1) give, bit for bit, only the stored ones written
/// (compact_batch.hpp). The derived ones are computed in registers and compared bit for bit with
/// their derivation: `two` / `fric` get compress()'s bits, `exact` whether expand() would give
/// every one of them (over all W lanes: the caller masks out padding). diag_n / diag_t: A_ii;
/// `singular` as pack_rows_simd's (normal or tangent). False, with nothing valid, when a row's
/// storage is not the usual one or without AVX2. `wide`: all 8 lanes of a row in one AVX-512
/// register, the sources gathered, where the CPU has AVX-512 (else 4 lanes per AVX2 register as
/// above); the same bits either way.
bool pack_compact_simd(const LcpProblem& p, const int* rn, const int* rt, const int* a, const int* bb, double omega,
                       CompactBatch& C, double* diag_n, double* diag_t, unsigned& singular, unsigned& two,
                       unsigned& fric, bool& exact, bool wide = false);

/// pack_compact_simd on staged sources (stage_sources, pgs_colored_layout.hpp): lane k's normal
/// row's 6 J entries at base + on[k], its tangent row's at base + ot[k] (slots 3–5 +0 when
/// bb[k] < 0), b_i in bn[k] and bt[k], M⁻¹ at im (LcpProblem::inv_mass), Δt = dt; the same
/// outputs, bit for bit, as pack_compact_simd on the rows they were copied from. False without
/// AVX2.
bool pack_compact_staged(const double* base, const int* on, const int* ot, const double* bn, const double* bt,
                         const int* a, const int* bb, const double* im, double dt, double omega, CompactBatch& C,
                         double* diag_n, double* diag_t, unsigned& singular, unsigned& two, unsigned& fric,
                         bool& exact, bool wide = false);

/// This build has pack_rows_simd's AVX2 code and this CPU runs it.
bool simd_pack_available();

}  // namespace dc::colored
