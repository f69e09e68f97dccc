#pragma once
// Private to the matrix-free PGS ("pgs", pgs_matrix_free.cpp): the two-point manifold block
// kernel, and what the kernels of pgs_matrix_free.cpp and this one share (the running θ /
// non-finite accumulator and the FMA clone attribute). Not part of the public API.
// The two normal rows of a manifold (one body pair, one normal) are solved as one 2 × 2 LCP
// exactly, by total enumeration in Box2D's order, because row by row biases the torque of every
// resting face the same way. Per manifold and sweep: tangent rows t0, t1 (bound ±μ max(0, λ_n)
// with the current λ_n), then the normal block. When round-off makes all four cases fail the
// block takes the row-by-row update; a badly conditioned pair is never a block (the test
// below). Circle scenes have no two-point manifolds, so their iterates are those of the
// row-by-row kernels bit for bit. Formulas [N, m/(N·s)]: docs/lcp.md "The two-point manifold block".
#include <array>

namespace dc::solvers {

// The multiply-adds on the chain are explicit std::fma (exactly rounded by IEEE on every
// CPU, so deterministic, docs/reproducibility.md). A build without FMA in its target
// (-DDC_NATIVE=OFF) gets an FMA clone of each kernel chosen at load time on FMA CPUs;
// only a CPU without FMA runs the default clone, whose fma() is glibc's exact software one.
#if defined(__x86_64__) && !defined(__FMA__) && defined(__GNUC__)
#define DC_PGS_FMA_CLONES __attribute__((target_clones("fma", "default")))
#else
#define DC_PGS_FMA_CLONES
#endif

/// Running θ and non-finite flag of one sweep.
struct SweepAcc {
  double theta = 0.0;
  bool bad = false;
};

/// Box2D's k_maxConditionNumber (b2_contact_solver.cpp): the largest estimated condition
/// number max(A_00, A_11)² / det of a 2 × 2 normal block solved as a block.
inline constexpr double kMaxBlockCondition = 1000.0;

/// True when the 2 × 2 block [A_00 A_01; A_01 A_11] (unscaled diagonals and off-diagonal) is
/// well enough conditioned to be solved as a block: max(A_00, A_11)² < kMaxBlockCondition ·
/// det (Box2D's test with the larger diagonal, so the order of the points does not matter).
inline bool manifold_block_conditioned(double a00, double a11, double a01) {
  const double big = a00 > a11 ? a00 : a11;
  return a00 > 0 && a11 > 0 && big * big < kMaxBlockCondition * (a00 * a11 - a01 * a01);
}

/// Two contacts of one body pair with one normal (a polygon manifold), both normal rows
/// plain [0, ∞) and non-singular. Rows are scaled by 1/A_ii like the other kernels' rows:
/// j* = J_i/A_ii, mj* = M⁻¹ J_iᵀ Δt (unscaled), b* = b_i/A_ii. The tangent fields are unused
/// (zero) for a frictionless manifold.
struct ManifoldBlock {
  std::array<double, 6> jn0, mjn0, jn1, mjn1;  // normal rows of point 0 and point 1
  std::array<double, 6> jt0, mjt0, jt1, mjt1;  // tangent rows (friction manifolds)
  double bn0, bn1, bt0, bt1;
  double mu0, mu1;
  double c01, c10;  // A_01/A_00, A_01/A_11
  double inv_det;   // 1/(1 − c01 c10)
  int la, lb, sa, sb;  // Δu offsets read (zero body when absent) and written (sink body)
};

/// One sweep over `count` friction manifolds, rows (n0, t0, n1, t1) at lam[4k .. 4k+3].
void sweep_manifolds_friction(const ManifoldBlock* c, int count, double* lam, double* u, SweepAcc& acc);
/// One sweep over `count` frictionless manifolds, rows (n0, n1) at lam[2k], lam[2k+1].
void sweep_manifolds_frictionless(const ManifoldBlock* c, int count, double* lam, double* u, SweepAcc& acc);

}  // namespace dc::solvers
