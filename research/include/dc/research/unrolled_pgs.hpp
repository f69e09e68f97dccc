#pragma once
// UnrolledPgs: k sweeps of the engine's row-by-row matrix-free projected Gauss–Seidel ("pgs"
// with SolverOptions::block_manifolds = false) on one contact LCP, differentiable with respect
// to the initial guess λ⁰ by reverse mode (docs/design.md §8.5). Same rows, row order and
// floating-point operations as the engine's kernels, so forward(λ⁰, k) is the engine's λ after
// k sweeps bit for bit (up to the sign of zero); the default "pgs" differs only on two-point
// manifolds (polygon faces), which circle scenes do not have. The forward pass records the
// projection piece of every row per sweep; the reverse pass applies the transposed maps in
// reverse order — exact except on kinks (derivation: docs/learning.md "Unrolled PGS and its
// adjoint"). Losses: residual_loss Σ r_i² of the natural map scaled by 1/A_ii [N²] (no λ*
// needed) and distance_loss Σ (λ_k − λ*)²; each adds its gradient to dλ_k and dΔu_k.
// Requires a problem assembled from a world, every row owned by a contact, A_ii > 0:
// InvalidArgument otherwise.
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
