#pragma once
// Dropout with rate p, "inverted" so that inference is the identity:
//   training:  m_i = [u_i ≥ p] / (1 − p),  u_i ~ U[0,1) from the bound dc::Rng,
//              y = m ⊙ x,  dx = m ⊙ dy;
//   inference: y = x.
// The mask is drawn serially (element order) before any parallel work, so a training run
// is reproducible for a fixed seed regardless of threads.
#include "dc/learning/layers/layer.hpp"

namespace dc {

class Dropout final : public Layer {
 public:
  /// p ∈ [0, 1); rng may be bound later with set_rng() (it is only needed in training).
  explicit Dropout(double rate, Rng* rng = nullptr);

  [[nodiscard]] std::string type() const override { return "dropout"; }
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] Shape output_shape(const Shape& in) const override { return in; }
  /// Throws InvalidArgument when training with p > 0 and no Rng bound.
  void forward(const Tensor& x, Tensor& y, bool training) override;
  void backward(const Tensor& x, const Tensor& y, const Tensor& dy, Tensor* dx) override;

  void set_rng(Rng* rng) { rng_ = rng; }
  /// Data-parallel training (data_parallel.hpp): the batch this process sees is samples
  /// [offset, offset + N) of a batch of `total`; a training forward draws the masks of all
  /// `total` samples (in element order, as one process would) and keeps its window's, so
  /// every process's masks and random stream equal the one-process run's. total = 0: off.
  void set_batch_window(int offset, int total) {
    window_offset_ = offset;
    window_total_ = total;
  }
  [[nodiscard]] double rate() const { return p_; }
  [[nodiscard]] const Tensor& mask() const { return mask_; }  ///< last training mask (empty: identity)

 private:
  double p_;
  Rng* rng_;
  Tensor mask_;
  bool identity_ = true;  ///< last forward was the identity (inference or p = 0)
  int window_offset_ = 0, window_total_ = 0;
};

}  // namespace dc
