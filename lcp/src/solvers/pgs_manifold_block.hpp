#pragma once
// Private to the matrix-free PGS ("pgs", pgs_matrix_free.cpp): the two-point manifold block
// kernel, and the pieces the kernels of pgs_matrix_free.cpp and this one share (the running
// θ / non-finite accumulator and the FMA clone attribute). Not part of the public API.
//
// Why a block. A polygon face resting on a face gives two contact points on the same body
// pair with the same normal (shape_collide.hpp: reference face, clipped incident face). PGS
// row by row solves point 1 and then point 2; until it converges the second point always sees
// the first one's fresh impulse and the first the second's stale one, which biases the torque
// of every such face the same way — a 20-box stack leans by 1 cm in 0.35 s at 100 sweeps
// (docs/engine.md). Box2D (b2ContactSolver::SolveVelocityConstraints, "block solver") solves
// the two normal rows of a manifold as one 2 × 2 LCP exactly. This kernel does the same.
//
// The 2 × 2 LCP. Rows 0, 1 (the two normal rows) with A_00, A_11 their diagonals and
// A_01 = J_0 M⁻¹ J_1ᵀ Δt [m/(N·s)]; the kernels keep rows scaled by 1/A_ii, so with
//     c01 = A_01/A_00,  c10 = A_01/A_11   (dimensionless, from the prepare stage)
// and the scaled residuals res_i = (J_i·Δu + b_i)/A_ii at the current λ = (a0, a1), the
// scaled residual of the block at λ_block = 0 (all other rows fixed) is
//     β0 = res0 − a0 − c01 a1,   β1 = res1 − a1 − c10 a0   [N]
// and the block's LCP is  w̃ = C x + β ≥ 0, x ≥ 0, xᵀw̃ = 0 with C = [1 c01; c10 1] (A's rows
// divided by their diagonals: a P-matrix when A's block is positive definite, so exactly one
// of the four cases below holds). Total enumeration, in Box2D's order:
//   1. both active:  x = −C⁻¹β: x0 = (c01 β1 − β0)/det, x1 = (c10 β0 − β1)/det, det = 1 − c01 c10;
//                    accept when x0 ≥ 0 and x1 ≥ 0
//   2. first only:   x0 = −β0, x1 = 0;  accept when x0 ≥ 0 and w̃1 = c10 x0 + β1 ≥ 0
//   3. second only:  x0 = 0, x1 = −β1;  accept when x1 ≥ 0 and w̃0 = c01 x1 + β0 ≥ 0
//   4. none:         x = 0;             accept when β0 ≥ 0 and β1 ≥ 0
// When round-off makes all four fail (a point exactly on a case boundary) the block takes the
// row-by-row update of the two rows instead (it never stalls; Box2D leaves λ unchanged).
//
// Conditioning. A manifold whose two points nearly coincide has a nearly singular block.
// Box2D keeps the block when k11² < k_maxConditionNumber·det(K) with k_maxConditionNumber =
// 1000, otherwise drops a point. Here a block is formed only when
//     max(A_00, A_11)² < kMaxBlockCondition · (A_00 A_11 − A_01²),  kMaxBlockCondition = 1000
// (Box2D's test with the larger diagonal, so the order of the points does not matter);
// otherwise the two contacts run through the row-by-row kernels (nothing is dropped).
//
// Friction. Each point's tangent row is solved right before the block, point 0 then point 1,
// with the bound ±μ max(0, λ_n) from the current (last sweep's) λ_n — Box2D's order: the
// normal rows, which carry the non-penetration, are solved last in each sweep and see the
// friction impulses of this sweep. Per manifold and sweep: t0, t1, then the 2 × 2 normal block.
//
// Circle scenes have no two-point manifolds: they never reach this kernel, and their iterates
// are those of the row-by-row kernels bit for bit.
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
/// well enough conditioned to be solved as a block (the test above).
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
