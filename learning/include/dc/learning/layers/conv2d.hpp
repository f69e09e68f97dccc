#pragma once
// Conv2d: k×k convolution (cross-correlation) with stride s and "same" padding, optional
// fused ReLU. x [N, Cin, H, W] → y [N, Cout, Ho, Wo], Ho = ⌈H/s⌉, Wo = ⌈W/s⌉; total padding
// per axis max((Ho−1)·s + k − H, 0), ⌊·/2⌋ before and the rest after (TensorFlow "SAME"; for
// odd k and s ∈ {1, 2} on odd sizes PyTorch's padding = (k−1)/2).
//
//   y[n, o, oy, ox] = b[o] + Σ_{c, ky, kx} w[o, c, ky, kx] · x[n, c, oy·s + ky − pt, ox·s + kx − pl]
//
// Direct AVX-512 kernels for output rows ≤ 64 wide (stride 1; forward also 3 × 3 stride 2),
// im2col + GEMM otherwise (docs/learning.md "Conv2d kernels"). Backward sums per-group dW
// accumulators in group order; groups depend on the batch size only, so results are
// deterministic for any thread count.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dc/learning/layers/layer.hpp"

namespace dc {

class Conv2d final : public Layer {
 public:
  /// Throws InvalidArgument for non-positive channels, even or non-positive kernel, stride < 1.
  Conv2d(int in_channels, int out_channels, int kernel = 3, int stride = 1, bool relu = false);

  [[nodiscard]] std::string type() const override { return "conv"; }
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] Shape output_shape(const Shape& in) const override;
  void forward(const Tensor& x, Tensor& y, bool training) override;
  void backward(const Tensor& x, const Tensor& y, const Tensor& dy, Tensor* dx) override;
  std::vector<ParamRef> parameters() override;
  void initialize(const Initializer& init, Rng& rng) override;

  [[nodiscard]] int in_channels() const { return cin_; }
  [[nodiscard]] int out_channels() const { return cout_; }
  [[nodiscard]] int kernel() const { return k_; }
  [[nodiscard]] int stride() const { return s_; }
  [[nodiscard]] bool relu() const { return relu_; }
  Tensor& weight() { return weight_; }  ///< [Cout, Cin, k, k]
  Tensor& bias() { return bias_; }      ///< [1, Cout, 1, 1]

 private:
  struct Geometry {
    int h, w, ho, wo, pad_top, pad_left, rows_per_tile;
  };
  [[nodiscard]] Geometry geometry(const Shape& in) const;
  void im2col(const float* x, const Geometry& g, int oy0, int oy1, float* col) const;
  void col2im(const float* col, const Geometry& g, int oy0, int oy1, float* dx) const;
  // The steps of backward() (conv2d.cpp): its plan (sizes, path, work groups), the scratch,
  // one work group (a run of samples, or one row tile of a single sample), the reduction.
  struct BackwardPlan;
  [[nodiscard]] BackwardPlan backward_plan(const Geometry& g, int N, bool has_dx) const;
  void prepare_backward(const BackwardPlan& b, const Geometry& g, const Tensor& y, const Tensor& dy, Tensor* dx);
  const float* masked_dy(const BackwardPlan& b, int n, int tid, const Tensor& y, const Tensor& dy);
  void backward_group(const BackwardPlan& b, const Geometry& g, int q, const Tensor& x, const Tensor& y,
                      const Tensor& dy, Tensor* dx);
  void backward_sample_direct(const BackwardPlan& b, const Geometry& g, int q, int n, const Tensor& x,
                              const float* gs, float* dxs);
  void backward_tiles(const BackwardPlan& b, const Geometry& g, int q, int n, int t_lo, int t_hi, const Tensor& x,
                      const float* gs, float* dxs);
  void reduce_backward(const BackwardPlan& b, const Geometry& g, Tensor* dx);

  int cin_, cout_, k_, s_;
  bool relu_;
  Tensor weight_, bias_, dweight_, dbias_;
  // Scratch, grown on demand and reused across calls (col_/dyr_ indexed by OpenMP thread).
  std::vector<Eigen::VectorXf> col_;    ///< X_col / dX_col of one tile (P × K)
  std::vector<Eigen::VectorXf> dyr_;    ///< dY masked by the fused ReLU (P × Cout)
  std::vector<Eigen::MatrixXf> dw_;     ///< dWᵀ accumulators (K × Cout), one per work group
  std::vector<Eigen::VectorXf> db_;     ///< db accumulators (Cout), one per work group
  Eigen::VectorXf dxcol_;               ///< whole-sample dX_col (batch 1, stride > 1)
  Eigen::VectorXf dymask_;              ///< ReLU-masked dY (batch 1)
  Eigen::MatrixXf wflip_;               ///< flipped, channel-transposed kernel (Cout·k² × Cin)
  // Direct stride-1 path (AVX-512, Wo ≤ 64; see conv2d.cpp): packed weights and padded rows.
  std::vector<float> wpk_;              ///< weights [Cout/OB][Cin][k][k][OB]
  std::vector<float> wpkf_;             ///< flipped kernel for dX [Cin/OB][Cout][k][k][OB]
  std::vector<Eigen::VectorXf> pad_;    ///< zero-padded dY rows of one tile, per thread
  std::vector<Eigen::VectorXf> xpad_;   ///< zero-padded input sample (direct dW), per thread
  std::vector<Eigen::VectorXf> dyz_;    ///< dY rows widened to whole vectors (direct dW), per thread
};

}  // namespace dc
