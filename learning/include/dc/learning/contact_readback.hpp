#pragma once
// ContactReadback: the Shepard read-back of a two-channel label grid at a step's contact
// points (what the cnn starter does with SphTransfer::gather), as an explicit linear map with
// its adjoint, for training through the solver (pgs_trainer.hpp).
//
//     v_k,c = bilinear(G_c)(q_k) / bilinear(S)(q_k)      (0 where q_k has no kernel support)
//
// S is the kernel-weight field of the points themselves (it depends on the contact positions
// only, never on G), so v is linear in G: v = R G with R the four bilinear weights of q_k's
// cell divided by bilinear(S)(q_k), and the adjoint is Ḡ += Rᵀ v̄. Tested equal to
// SphTransfer::gather.
#include <span>
#include <vector>

#include "dc/engine/vec2.hpp"
#include "dc/warmstart/sph_grid.hpp"
#include "dc/warmstart/sph_transfer.hpp"

namespace dc {

class ContactReadback {
 public:
  ContactReadback() = default;
  /// Stencils and Shepard denominators of `points` on `transfer`'s grid (Shepard mode, two
  /// channels expected; the transfer's weight grid is overwritten).
  ContactReadback(SphTransfer& transfer, std::span<const Vec2> points);

  [[nodiscard]] int points() const { return static_cast<int>(stencil_.size()); }
  /// out[2k + c] = read-back of channel c (of the NCHW plane pair `grid`, 2·ny·nx floats) at point k.
  void forward(const float* grid, std::span<double> out) const;
  /// dgrid[c·ny·nx + node] += Σ_k R_k,node · dout[2k + c] (2·ny·nx floats).
  void adjoint(std::span<const double> dout, float* dgrid) const;

 private:
  std::vector<BilinearStencil> stencil_;
  std::vector<double> weight_;  // bilinear(S)(q_k), 0 when unsupported
  int nx_ = 0, ny_ = 0;
};

}  // namespace dc
