#pragma once
// ContactReadback: the read-back of a model's two-channel output grid G at a step's contact
// points as an explicit linear map v = R G with its adjoint Ḡ += Rᵀ v̄, for training through
// the solver (pgs_trainer.hpp) and for the cnn starter. Two kinds (labels.hpp LabelKind):
//   Shepard: v_k,c = bilinear(G_c)(q_k) / bilinear(S)(q_k) (0 without kernel support), S the
//            kernel-weight field of the points alone; bit-equal to SphTransfer::gather.
//   Gain:    v_k,c = λp_k,c · bilinear(D_c ⊙ G_c)(q_k) / bilinear(D_c)(q_k) (0 where
//            bilinear(D_c) = 0), D_c = Σ_k W(|x − q_k|) λp_k,c² the splat of the builtin guess's
//            squares: G is a gain field; for G = N/D this is sph-gain's read-back. D depends on
//            λ_prev only (known ahead of the solve), so v is linear in G.
#include <array>
#include <span>
#include <vector>

#include "dc/core/vec2.hpp"
#include "dc/sph/sph_grid.hpp"
#include "dc/sph/sph_transfer.hpp"

namespace dc {

class ContactReadback {
 public:
  ContactReadback() = default;
  /// Shepard: stencils and denominators of `points` on `transfer`'s grid (Shepard mode, two
  /// channels expected; the transfer's weight grid is overwritten).
  ContactReadback(SphTransfer& transfer, std::span<const Vec2> points);
  /// Gain: `lambda_prev` holds (λp_n, λp_t) per point (2·points.size() values); the transfer's
  /// kernel and grid (two channels) give D; its value grid is overwritten.
  static ContactReadback gain(SphTransfer& transfer, std::span<const Vec2> points, std::span<const double> lambda_prev);

  [[nodiscard]] int points() const { return static_cast<int>(stencil_.size()); }
  /// out[2k + c] = read-back of channel c (of the NCHW plane pair `grid`, 2·ny·nx values) at point k.
  void forward(const float* grid, std::span<double> out) const;
  void forward(const double* grid, std::span<double> out) const;
  /// dgrid[c·ny·nx + node] += Σ_k R_k,node · dout[2k + c] (2·ny·nx floats).
  void adjoint(std::span<const double> dout, float* dgrid) const;

 private:
  template <class T>
  void forward_impl(const T* grid, std::span<double> out) const;

  std::vector<BilinearStencil> stencil_;
  std::vector<double> weight_;               // Shepard: bilinear(S)(q_k), 0 when unsupported
  std::vector<std::array<double, 8>> coef_;  // Gain: channel c's corners 00, 01, 10, 11 at 4c..4c+3
  bool gain_ = false;
  int nx_ = 0, ny_ = 0;
};

}  // namespace dc
