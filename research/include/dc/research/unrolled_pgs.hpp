#pragma once
// UnrolledPgs: k sweeps of the engine's matrix-free projected Gauss–Seidel ("pgs",
// lcp/src/solvers/pgs_matrix_free.cpp) on one contact LCP, differentiable with respect to
// the initial guess λ⁰ by reverse mode (docs/design.md §8.5: train the warm start for what PGS
// pays). Same rows, same row order, same floating-point operations in the same order as the
// engine's kernels, so forward(λ⁰, k) returns the engine's λ after k fixed sweeps bit for bit
// (up to the sign of zero; tested) — the row-by-row engine kernels, i.e. "pgs" with
// SolverOptions::block_manifolds = false. On problems with two-point manifolds (two contacts
// of one body pair with one normal: polygon faces) the engine's default "pgs" solves each
// manifold's normal rows as one 2 × 2 block instead (lcp/src/solvers/pgs_manifold_block.hpp)
// and its iterates differ from these (same fixed point); circle scenes, the ones trained on,
// have no such manifolds, so there the two agree bit for bit.
//
// One row update (J_i and b_i pre-scaled by 1/A_ii, Δu = Δt M⁻¹ Jᵀ λ kept as the state):
//     r = J_i·Δu + b_i,  y = λ_i − r,  x = P_i(y; λ_n(i)),  d = x − λ_i,  λ_i ← x,  Δu += (Δt M⁻¹ J_iᵀ) d
// with P_i = max(0, ·) for a normal row and clamp(·, −μλ_n⁺, μλ_n⁺) for a friction row (λ_n the
// current, i.e. this sweep's, normal value). P is piecewise linear: x = y (interior),
// x = 0 / a fixed bound (no dependence), or x = ±μ λ_n (a friction bound, linear in λ_n). The
// forward pass records which piece each row took in each sweep (one byte per row per sweep)
// and the reverse pass applies the transposed linear maps in reverse order:
//     d̄ = (Δt M⁻¹ J_iᵀ)·Δū,  x̄ = λ̄_i + d̄,  ȳ = ∂x/∂y · x̄,  λ̄_n += ∂x/∂λ_n · x̄,
//     λ̄_i ← ȳ − d̄,  Δū ← Δū − J_iᵀ ȳ   (Δū of the row's bodies, replaced, not summed)
// and finally λ̄⁰ += J (Δt M⁻¹ Δū⁰) for Δu⁰ = Δt M⁻¹ Jᵀ λ⁰. The gradient is exact wherever no
// row sits exactly on a kink (a set of measure zero; at a kink the piece taken in the forward
// pass is used, a one-sided derivative).
//
// Losses (each returns the value and adds its gradient to dλ_k and dΔu_k):
//  * residual_loss: Σ_i r_i² of the SCALED natural map r_i = λ_i − P_i(λ_i − w_i/A_ii) at λ_k,
//    w = Aλ + b. Scaling by 1/A_ii puts every row in newtons (A_ii ~ Δt/m, so the unscaled map
//    mixes N with m/s and weights light bodies 1/m² more); r_i is the step a Jacobi sweep would
//    take, the quantity θ_k measures for Gauss–Seidel. Zero exactly at a solution. Needs no λ*.
//  * distance_loss: Σ_i (λ_k,i − λ*_i)² against an oracle solution.
//
// Requirements: a problem assembled from a world (J, M⁻¹, Δt and contact constraints; every
// row owned by a contact; no singular row A_ii ≤ 0): InvalidArgument otherwise.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"

namespace dc {

class UnrolledPgs {
 public:
  /// Packs the rows of `p` (copied; `p` may go away). Throws InvalidArgument (see above).
  explicit UnrolledPgs(const LcpProblem& p);

  [[nodiscard]] int rows() const { return static_cast<int>(rows_.size()); }
  /// 3·bodies: the size of Δu.
  [[nodiscard]] int velocity_entries() const { return nu_; }

  /// k ≥ 0 sweeps from λ⁰ (used as given: project it first, as the solver's caller does).
  /// Returns λ_k; records the pieces for backward(). InvalidArgument on a size mismatch.
  const Eigen::VectorXd& forward(const Eigen::VectorXd& lambda0, int sweeps);
  [[nodiscard]] const Eigen::VectorXd& lambda() const { return lam_; }
  /// Δu_k = Δt M⁻¹ Jᵀ λ_k as the sweeps maintained it (velocity_entries() values).
  [[nodiscard]] Eigen::Map<const Eigen::VectorXd> velocity() const {
    return Eigen::Map<const Eigen::VectorXd>(u_.data(), nu_);
  }

  /// Reverse pass of the last forward(): dL/dλ⁰ from dL/dλ_k and dL/dΔu_k (dlam_k: rows();
  /// du_k: velocity_entries() or empty for 0).
  [[nodiscard]] Eigen::VectorXd backward(const Eigen::VectorXd& dlam_k, const Eigen::VectorXd& du_k) const;

  /// Σ r_i² of the scaled natural map at the current λ_k, Δu_k (see the file comment); adds
  /// the gradient to dlam (rows()) and du (velocity_entries()), which must be sized.
  double residual_loss(Eigen::VectorXd& dlam, Eigen::VectorXd& du) const;
  /// The scaled natural-map residual vector r at the current λ_k (rows() values).
  [[nodiscard]] Eigen::VectorXd residual() const;
  /// Σ (λ_k − target)²; adds 2(λ_k − target) to dlam.
  double distance_loss(const Eigen::VectorXd& target, Eigen::VectorXd& dlam) const;

 private:
  struct Row {
    std::array<double, 6> j{};   // J_i / A_ii on (body a: v_x, v_y, ω, body b: v_x, v_y, ω)
    std::array<double, 6> mj{};  // Δt M⁻¹ J_iᵀ on the same entries
    double b = 0.0;              // b_i / A_ii [N]
    double lo = 0.0, hi = 0.0;   // fixed bounds (0, 0 for friction rows)
    double mu = 0.0;             // friction rows
    int coupled = -1;            // normal row of a friction row, −1 otherwise
    int la = 0, lb = 0, sa = 0, sb = 0;  // Δu offsets read / written (zero and sink bodies)
    bool has_a = false, has_b = false;
    bool plain_normal = false;   // bounds [0, ∞), no coupling: the engine's branch form
  };
  /// The piece of P a row took (recorded per sweep).
  enum Piece : std::uint8_t { Interior = 0, Fixed = 1, Upper = 2, Lower = 3 };
  /// One row update of the forward pass; returns its piece.
  Piece update(const Row& r, int i, double* lam, double* u) const;
  /// Scaled natural map of row i at (lam, u): returns r_i and its piece.
  double natural_map(const Row& r, int i, const double* lam, const double* u, Piece& piece) const;

  std::vector<Row> rows_;
  SparseRowMatrix J_;
  Eigen::VectorXd inv_mass_;
  double dt_ = 0.0;
  int nu_ = 0;                       // 3·bodies; zero body at nu_, sink at nu_ + 3
  int sweeps_ = 0;
  Eigen::VectorXd lam_;
  std::vector<double> u_;
  std::vector<std::uint8_t> pieces_;  // sweeps_ × rows()
};

}  // namespace dc
