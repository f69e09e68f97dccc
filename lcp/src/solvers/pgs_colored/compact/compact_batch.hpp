#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): the compact batch, a Batch
// (pgs_colored_batch.hpp) without the coefficients that follow bit for bit from the ones it keeps.
//
// What the engine's assembly writes (engine/src/assembly): body b's linear entries of a row are
// body a's negated (±n, ±t), and the tangent is the normal turned, t = (−n_y, n_x), on the same
// bodies; M⁻¹ is isotropic for v_x, v_y (m⁻¹ twice). The packed coefficients are
// j_s = ((0 + J_is)·(1/A_ii))·ω and mj_s = ((0 + J_is)·m⁻¹_s)·Δt (pgs_colored_layout.cpp), so
//   j_3 = 0 − j_0,   j_4 = 0 − j_1                       (two-body lanes; else +0)
//   mjt_0 = 0 − mjn_1,  mjt_1 = mjn_0,  mjt_3 = 0 − mjn_4,  mjt_4 = mjn_3   (lanes with friction; else +0)
// exactly: negation commutes with every rounding, and 0 − x turns a +0 into +0 as the pack's
// 0 + J_is does. The products of different A_ii (j of the normal and of the tangent) or of
// different masses (mj of body a and of body b) are not related exactly and stay stored: 19 of
// Batch's 27 doubles per lane.
//
// compress() does not rely on that structure: it derives, expands again and compares every bit
// with the full batch, so a problem whose J or M⁻¹ is not of that form (a general M⁻¹, a
// non-isotropic one, rows written by hand) keeps the full layout, and the compact one gives the
// full one's iterates bit for bit whenever it is used.
#include <cstdint>

#include <Eigen/Core>

#include "dc/lcp/lcp_problem.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"

namespace dc::colored {

struct Prepared;

/// A Batch less the derivable coefficients. Slots of jn/jt: 0, 1, 2, 5 of Batch's; of mjt: 2, 5.
/// Bit k of `two`: lane k's slots 3, 4 of jn/jt are derived (else +0); bit k of `fric`: its mjt
/// slots 0, 1, 3, 4 are derived (else +0). (Bit masks: an AVX-512 mask register as they are.)
struct alignas(64) CompactBatch {
  double jn[4][W], jt[4][W];
  double mjn[6][W], mjt[2][W];
  double bn[W], bt[W], mu[W];
  std::int32_t la[W], lb[W];
  std::uint8_t ka[W], kb[W];
  std::uint8_t two = 0, fric = 0;
  int count = 0;
};
static_assert(sizeof(CompactBatch) % 64 == 0);

/// The rows J_i/A_ii, b/A_ii, μ, bodies and count of C's full batch (what the residual reads:
/// not M⁻¹JᵀΔt), bit for bit as the pack wrote them when compress(B, C) returned true. Inline so
/// that each caller's copy is compiled for its ISA.
inline void expand_rows(const CompactBatch& C, Batch& B) {
  constexpr int kept[4] = {0, 1, 2, 5};
  for (int q = 0; q < 4; ++q)
    for (int k = 0; k < W; ++k) {
      B.jn[kept[q]][k] = C.jn[q][k];
      B.jt[kept[q]][k] = C.jt[q][k];
    }
  for (int k = 0; k < W; ++k) {
    const bool two = ((C.two >> k) & 1) != 0;
    B.jn[3][k] = two ? 0.0 - C.jn[0][k] : 0.0;
    B.jn[4][k] = two ? 0.0 - C.jn[1][k] : 0.0;
    B.jt[3][k] = two ? 0.0 - C.jt[0][k] : 0.0;
    B.jt[4][k] = two ? 0.0 - C.jt[1][k] : 0.0;
    B.bn[k] = C.bn[k];
    B.bt[k] = C.bt[k];
    B.mu[k] = C.mu[k];
    B.la[k] = C.la[k];
    B.lb[k] = C.lb[k];
    B.ka[k] = C.ka[k];
    B.kb[k] = C.kb[k];
  }
  B.count = C.count;
}

/// The full batch of C: expand_rows and M⁻¹JᵀΔt.
inline void expand(const CompactBatch& C, Batch& B) {
  expand_rows(C, B);
  for (int s = 0; s < 6; ++s)
    for (int k = 0; k < W; ++k) B.mjn[s][k] = C.mjn[s][k];
  for (int k = 0; k < W; ++k) {
    const bool fric = ((C.fric >> k) & 1) != 0;
    B.mjt[0][k] = fric ? 0.0 - C.mjn[1][k] : 0.0;
    B.mjt[1][k] = fric ? C.mjn[0][k] : 0.0;
    B.mjt[3][k] = fric ? 0.0 - C.mjn[4][k] : 0.0;
    B.mjt[4][k] = fric ? C.mjn[3][k] : 0.0;
    B.mjt[2][k] = C.mjt[0][k];
    B.mjt[5][k] = C.mjt[1][k];
  }
}

/// C ← B less its derivable coefficients; true when expand(C) reproduces every bit of B's
/// coefficients, bodies and count (else C is undefined and B must be swept as it is).
bool compress(const Batch& B, CompactBatch& C);

/// fill_batch (pgs_colored_layout.hpp) of batch `bi` and over_relax by ω (≠ 1), compressed into
/// out.compact[bi]; when it does not compress exactly (or `full` is set), the full batch goes to
/// out.batches[bi] instead and false is returned (true: out.batches[bi] not written). A batch of
/// single contacts with friction and rows in the usual storage is packed straight into the
/// compact batch (pack_compact_simd, pgs_colored_pack_simd.hpp, or pack_compact_staged from the
/// records of a staged problem: only the stored coefficients are written, the derived ones
/// compared in registers with compress()'s derivation, the same verdict and bits); other batches
/// are filled full in cache and compressed.
bool fill_compact(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Prepared& out, int bi,
                  double* lp, double* other, double omega, bool full);

using CompactKernel = void (*)(const CompactBatch* batches, int b0, int b1, const double* in, double* out, double* u,
                               Acc& acc);
/// The sweep kernels on compact batches: each batch expanded in cache and swept by the full
/// kernel of the ISA (sweep_scalar, sweep_avx2, sweep_avx512), so the bits are theirs.
void sweep_compact_scalar(const CompactBatch* batches, int b0, int b1, const double* in, double* out, double* u,
                          Acc& acc);
void sweep_compact_avx2(const CompactBatch* batches, int b0, int b1, const double* in, double* out, double* u,
                        Acc& acc);
void sweep_compact_avx512(const CompactBatch* batches, int b0, int b1, const double* in, double* out, double* u,
                          Acc& acc);

}  // namespace dc::colored
