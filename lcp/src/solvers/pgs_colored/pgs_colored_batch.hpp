#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): the packed batch of 8 contacts of one
// colour and the three sweep kernels over batches (scalar, AVX2, AVX-512), which perform per lane
// the same floating-point operations in the same order, so all three give bit-identical iterates,
// θ and non-finite flags.
//
// Kernel contract. sweep_*(batches, b0, b1, in, out, u, acc) solves batches [b0, b1) in order:
// contact k of batch bi reads λ^{k−1} from in[16·bi + k] (normal) and in[16·bi + 8 + k]
// (tangent), writes λ^k to the same entries of `out` (in ≠ out: the caller keeps λ^{k−1}
// without copying it), and updates Δu in place (kStride doubles per body, the
// zero body at `Prepared::body_entries` is read, never written). acc.theta = max(acc.theta,
// max |λ^k − λ^{k−1}|); acc.bad is set when a new λ (or a tangent row's unprojected value) or
// one of the 6 body velocities a contact stores is ±∞ or NaN — the Δu check is fused into the
// sweep (x·0 + … is NaN exactly when some x is not finite), so no pass over Δu follows a sweep.
//
// Pair batches (two-point manifolds: two contacts of one body pair with one normal, in one lane,
// as "pgs" solves them, pgs_manifold_block.hpp). sweep_pairs_*(pairs, b0, b1, in, out, u, acc)
// solves pair batches [b0, b1) in order; lane k of pair batch bi has its rows at in/out + 32·bi +
// {0, 8, 16, 24} + k: λ_n0, λ_t0, λ_n1, λ_t1. Per lane: the tangent rows t0 and t1 (bounds
// μ max(0, λ_n) with the normal λ of the previous sweep), then the 2 × 2 normal block by total
// enumeration of its four cases (both points, point 0 only, point 1 only, neither, in that
// priority); a lane whose block is not solved as one (`block` = 0: badly conditioned) and a
// block whose four cases all fail (round-off, NaN) take the Gauss–Seidel update of n0 then n1.
// θ, the non-finite flag and the Δu handling are those of the contact kernels.
#include <cstdint>

namespace dc::colored {

constexpr int W = 8;        // lanes per batch (one AVX-512 register, two AVX2 registers)
constexpr int kStride = 4;  // doubles per body in Δu (v_x, v_y, ω, padding)

struct alignas(64) Batch {
  double jn[6][W], mjn[6][W], jt[6][W], mjt[6][W];  // J_i/A_ii and M⁻¹J_iᵀΔt per slot
  double bn[W], bt[W], mu[W];                       // b_i/A_ii [N], μ
  std::int32_t la[W], lb[W];                        // Δu offsets (4·body; zero body if absent)
  std::uint8_t ka[W], kb[W];                        // 1 when the lane writes body a / b back
  int count = 0;                                    // lanes in use (the rest: zero padding)
};
static_assert(sizeof(Batch) % 64 == 0);

/// One lane = one two-point manifold: rows of point 0 (n0, t0) and point 1 (n1, t1), scaled like a
/// Batch's; c01 = A_01/A_00, c10 = A_01/A_11, inv_det = 1/(1 − c01·c10); block = 1 when the normal
/// block is solved as one, 0 otherwise (and for padding lanes).
struct alignas(64) PairBatch {
  double jn0[6][W], mjn0[6][W], jt0[6][W], mjt0[6][W];
  double jn1[6][W], mjn1[6][W], jt1[6][W], mjt1[6][W];
  double bn0[W], bt0[W], mu0[W], bn1[W], bt1[W], mu1[W];
  double c01[W], c10[W], inv_det[W], block[W];
  std::int32_t la[W], lb[W];
  std::uint8_t ka[W], kb[W];
  int count = 0;
};
static_assert(sizeof(PairBatch) % 64 == 0);

struct Acc {
  double theta = 0.0;
  bool bad = false;
};

using SweepKernel = void (*)(const Batch* batches, int b0, int b1, const double* in, double* out, double* u,
                             Acc& acc);

void sweep_scalar(const Batch* batches, int b0, int b1, const double* in, double* out, double* u, Acc& acc);
/// Defined only where the compiler can target the ISA (x86-64 GCC/Clang); call only when
/// cpu_has_avx2() / cpu_has_avx512() is true.
void sweep_avx2(const Batch* batches, int b0, int b1, const double* in, double* out, double* u, Acc& acc);
void sweep_avx512(const Batch* batches, int b0, int b1, const double* in, double* out, double* u, Acc& acc);

using PairKernel = void (*)(const PairBatch* pairs, int b0, int b1, const double* in, double* out, double* u,
                           Acc& acc);
void sweep_pairs_scalar(const PairBatch* pairs, int b0, int b1, const double* in, double* out, double* u, Acc& acc);
void sweep_pairs_avx2(const PairBatch* pairs, int b0, int b1, const double* in, double* out, double* u, Acc& acc);
void sweep_pairs_avx512(const PairBatch* pairs, int b0, int b1, const double* in, double* out, double* u, Acc& acc);

/// This build has the kernel and this CPU (and OS) runs it: AVX2 + FMA, AVX-512 F/DQ/VL.
bool cpu_has_avx2();
bool cpu_has_avx512();
/// The CPU's vendor is AMD (x86-64 GCC/Clang builds; false elsewhere).
bool cpu_is_amd();
/// The CPU's family (CPUID leaf 1: base family + extended family; 0x19 Zen 3/4, 0x1A Zen 5;
/// 0 where unknown).
int cpu_family();

// std::max(a, b) and std::min(a, b) as the vector kernels write them (compare + select).
inline double max_of(double a, double b) { return (a < b) ? b : a; }
inline double min_of(double a, double b) { return (b < a) ? b : a; }

}  // namespace dc::colored
