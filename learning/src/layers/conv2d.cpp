#include "dc/learning/layers/conv2d.hpp"

#include <algorithm>
#include <cstring>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "dc/core/error.hpp"
#include "dc/learning/initializer.hpp"
#include "layers/conv_direct.hpp"
#include "omp_util.hpp"

namespace dc {

namespace {
// Target size of one X_col tile in floats (256 KiB): fits L2 together with Wᵀ and the
// output tile, so the GEMM streams from cache instead of memory.
constexpr long kTileFloats = 64 * 1024;
// Below this many multiply-adds a call runs on one thread: opening a parallel region costs
// more than such a call's arithmetic, and much more when the cores are shared. It is also below
// the size at which Eigen would parallelise a single GEMM itself (work ≥ 2·50 000), so
// Eigen never opens nested parallel regions here: all threading is ours.
constexpr double kParallelMacs = 1e5;

using detail::block_channels;
using detail::direct_available;
using detail::direct_tile;
using detail::kLanes;
using detail::pack_weights;
using detail::pad_rows;
using detail::pad_rows_s2;
using detail::padded_width;
using detail::vec_count;

using MatMap = Eigen::Map<Eigen::MatrixXf>;
using CMatMap = Eigen::Map<const Eigen::MatrixXf>;
using StridedMap = Eigen::Map<Eigen::MatrixXf, 0, Eigen::OuterStride<>>;
using CStridedMap = Eigen::Map<const Eigen::MatrixXf, 0, Eigen::OuterStride<>>;

template <class T>
void grow(std::vector<T>& v, std::size_t threads) {
  if (v.size() < threads) v.resize(threads);
}
void grow(Eigen::VectorXf& v, Eigen::Index n) {
  if (v.size() < n) v.resize(n);
}
}  // namespace

Conv2d::Conv2d(int in_channels, int out_channels, int kernel, int stride, bool relu)
    : cin_(in_channels), cout_(out_channels), k_(kernel), s_(stride), relu_(relu) {
  if (cin_ <= 0 || cout_ <= 0) throw InvalidArgument("Conv2d: channel counts must be positive");
  if (k_ <= 0 || k_ % 2 == 0) throw InvalidArgument("Conv2d: kernel must be odd and positive, got " + std::to_string(k_));
  if (s_ < 1) throw InvalidArgument("Conv2d: stride must be >= 1, got " + std::to_string(s_));
  weight_ = Tensor(cout_, cin_, k_, k_);
  dweight_ = Tensor(cout_, cin_, k_, k_);
  bias_ = Tensor(1, cout_, 1, 1);
  dbias_ = Tensor(1, cout_, 1, 1);
}

std::string Conv2d::describe() const {
  return "conv " + std::to_string(cin_) + "->" + std::to_string(cout_) + " k" + std::to_string(k_) + " s" +
         std::to_string(s_) + (relu_ ? " relu" : "");
}

Shape Conv2d::output_shape(const Shape& in) const {
  if (in.c != cin_)
    throw InvalidArgument("Conv2d (" + describe() + "): input has " + std::to_string(in.c) + " channels");
  if (in.h <= 0 || in.w <= 0) throw InvalidArgument("Conv2d: empty input " + in.str());
  return {in.n, cout_, detail::ceil_div(in.h, s_), detail::ceil_div(in.w, s_)};
}

Conv2d::Geometry Conv2d::geometry(const Shape& in) const {
  const Shape out = output_shape(in);
  Geometry g{};
  g.h = in.h;
  g.w = in.w;
  g.ho = out.h;
  g.wo = out.w;
  // "same" padding: total = max((Ho−1)·s + k − H, 0), the smaller half before.
  g.pad_top = std::max((g.ho - 1) * s_ + k_ - g.h, 0) / 2;
  g.pad_left = std::max((g.wo - 1) * s_ + k_ - g.w, 0) / 2;
  const long K = static_cast<long>(cin_) * k_ * k_;
  g.rows_per_tile = static_cast<int>(std::clamp<long>(kTileFloats / (K * g.wo), 1, g.ho));
  return g;
}

// X_col for output rows [oy0, oy1): column (c, ky, kx) is the input plane c shifted by
// (ky − pt, kx − pl) and subsampled by s, zero outside the image. P = (oy1−oy0)·Wo rows.
// Free of Conv2d state so that it also builds the patches of dY for the stride-1 dX.
static void im2col_planes(const float* x, int channels, int h, int w, int k, int s, int pad_top, int pad_left, int wo,
                   int oy0, int oy1, float* col) {
  const int P = (oy1 - oy0) * wo;
  for (int c = 0; c < channels; ++c) {
    const float* plane = x + static_cast<std::size_t>(c) * h * w;
    for (int ky = 0; ky < k; ++ky) {
      for (int kx = 0; kx < k; ++kx) {
        float* dst = col + static_cast<std::size_t>((c * k + ky) * k + kx) * P;
        const int dxoff = kx - pad_left;
        // ox range whose source column ix = ox·s + dxoff lies inside [0, W).
        const int ox_lo = std::clamp(detail::ceil_div(-dxoff, s), 0, wo);
        const int ox_hi = std::clamp(detail::floor_div(w - 1 - dxoff, s) + 1, ox_lo, wo);
        for (int oy = oy0; oy < oy1; ++oy, dst += wo) {
          const int iy = oy * s + ky - pad_top;
          if (iy < 0 || iy >= h) {
            std::memset(dst, 0, sizeof(float) * wo);
            continue;
          }
          const float* src = plane + static_cast<std::size_t>(iy) * w + dxoff;
          for (int ox = 0; ox < ox_lo; ++ox) dst[ox] = 0.0f;
          if (s == 1) {
            std::memcpy(dst + ox_lo, src + ox_lo, sizeof(float) * (ox_hi - ox_lo));
          } else {
            for (int ox = ox_lo; ox < ox_hi; ++ox) dst[ox] = src[ox * s];
          }
          for (int ox = ox_hi; ox < wo; ++ox) dst[ox] = 0.0f;
        }
      }
    }
  }
}

// The direct dW kernel (the forward and dX kernels are in conv_direct.cpp).
namespace {
#if defined(__AVX512F__)
// dWᵀ (K × Cout, column-major, K = C·9) += Σ_pixels dY ⊗ shifted x for a 3 × 3 stride-1 conv
// over a whole sample: xp [C][Ho+2][Wp] padded input (p = 1); dY[o, j, lane] at
// dy[o·dy_plane + j·dy_row + lane], zero for lanes ≥ Wo up to VB·16. Per (c, ky) and OB output channels, 3·OB vector accumulators (one
// per kx) run over all rows; each lane sum is reduced once at the end.
template <int VB, int OB>
void direct_dw3(const float* xp, int C, int Wp, const float* dy, long dy_plane, int dy_row, int cout, int ho,
                float* dw) {
  const int K = C * 9;
  const int Hp = ho + 2;
  for (int c = 0; c < C; ++c) {
    for (int ky = 0; ky < 3; ++ky) {
      for (int ob = 0; ob < cout / OB; ++ob) {
        __m512 acc[OB][3];
        for (int o = 0; o < OB; ++o)
          for (int kx = 0; kx < 3; ++kx) acc[o][kx] = _mm512_setzero_ps();
        const float* d0 = dy + static_cast<std::size_t>(ob) * OB * dy_plane;
        for (int j = 0; j < ho; ++j) {
          const float* xr = xp + (static_cast<std::size_t>(c) * Hp + j + ky) * Wp;
          const float* dr = d0 + static_cast<std::size_t>(j) * dy_row;
          for (int v = 0; v < VB; ++v) {
            __m512 x0 = _mm512_loadu_ps(xr + v * kLanes);
            __m512 x1 = _mm512_loadu_ps(xr + 1 + v * kLanes);
            __m512 x2 = _mm512_loadu_ps(xr + 2 + v * kLanes);
            __asm__("" : "+v"(x0), "+v"(x1), "+v"(x2));  // one load each (see direct_rows)
            for (int o = 0; o < OB; ++o) {
              __m512 d = _mm512_loadu_ps(dr + static_cast<std::size_t>(o) * dy_plane + v * kLanes);
              __asm__("" : "+v"(d));
              acc[o][0] = _mm512_fmadd_ps(d, x0, acc[o][0]);
              acc[o][1] = _mm512_fmadd_ps(d, x1, acc[o][1]);
              acc[o][2] = _mm512_fmadd_ps(d, x2, acc[o][2]);
            }
          }
        }
        for (int o = 0; o < OB; ++o)
          for (int kx = 0; kx < 3; ++kx)
            dw[(c * 9 + ky * 3 + kx) + static_cast<std::size_t>(ob * OB + o) * K] += _mm512_reduce_add_ps(acc[o][kx]);
      }
    }
  }
}
#endif

void direct_dw_sample(const float* xp, int C, int Wp, const float* dy, long dy_plane, int dy_row, int cout, int ho,
                      int wo, float* dw) {
#if defined(__AVX512F__)
  const int ob = cout % 8 == 0 ? 8 : cout % 4 == 0 ? 4 : cout % 2 == 0 ? 2 : 1;
#define DC_DW(VB)                                                        \
  switch (ob) {                                                          \
    case 8: direct_dw3<VB, 8>(xp, C, Wp, dy, dy_plane, dy_row, cout, ho, dw); break;      \
    case 4: direct_dw3<VB, 4>(xp, C, Wp, dy, dy_plane, dy_row, cout, ho, dw); break;      \
    case 2: direct_dw3<VB, 2>(xp, C, Wp, dy, dy_plane, dy_row, cout, ho, dw); break;      \
    default: direct_dw3<VB, 1>(xp, C, Wp, dy, dy_plane, dy_row, cout, ho, dw); break;     \
  }
  switch (vec_count(wo)) {
    case 1: DC_DW(1) break;
    case 2: DC_DW(2) break;
    case 3: DC_DW(3) break;
    default: DC_DW(4) break;
  }
#undef DC_DW
#else
  (void)xp, (void)C, (void)Wp, (void)dy, (void)dy_plane, (void)dy_row, (void)cout, (void)ho, (void)wo, (void)dw;
#endif
}

// Output rows per direct tile: the padded buffer C·(rows + k − 1)·Wp stays ≤ kTileFloats.
int direct_rows_per_tile(int C, int k, int wp, int ho) {
  const long r = kTileFloats / (static_cast<long>(C) * wp) - (k - 1);
  return static_cast<int>(std::clamp<long>(r, 1, ho));
}
}  // namespace

void Conv2d::im2col(const float* x, const Geometry& g, int oy0, int oy1, float* col) const {
  im2col_planes(x, cin_, g.h, g.w, k_, s_, g.pad_top, g.pad_left, g.wo, oy0, oy1, col);
}

// Adjoint of im2col: dx[c, iy, ix] += dX_col[p, (c, ky, kx)] for every in-image source.
void Conv2d::col2im(const float* col, const Geometry& g, int oy0, int oy1, float* dx) const {
  const int P = (oy1 - oy0) * g.wo;
  for (int c = 0; c < cin_; ++c) {
    float* plane = dx + static_cast<std::size_t>(c) * g.h * g.w;
    for (int ky = 0; ky < k_; ++ky) {
      for (int kx = 0; kx < k_; ++kx) {
        const float* src = col + static_cast<std::size_t>((c * k_ + ky) * k_ + kx) * P;
        const int dxoff = kx - g.pad_left;
        const int ox_lo = std::clamp(detail::ceil_div(-dxoff, s_), 0, g.wo);
        const int ox_hi = std::clamp(detail::floor_div(g.w - 1 - dxoff, s_) + 1, ox_lo, g.wo);
        for (int oy = oy0; oy < oy1; ++oy, src += g.wo) {
          const int iy = oy * s_ + ky - g.pad_top;
          if (iy < 0 || iy >= g.h) continue;
          float* dst = plane + static_cast<std::size_t>(iy) * g.w + dxoff;
          if (s_ == 1) {
            for (int ox = ox_lo; ox < ox_hi; ++ox) dst[ox] += src[ox];
          } else {
            for (int ox = ox_lo; ox < ox_hi; ++ox) dst[ox * s_] += src[ox];
          }
        }
      }
    }
  }
}

void Conv2d::forward(const Tensor& x, Tensor& y, bool /*training*/) {
  const Geometry g = geometry(x.shape());
  const int N = x.n();
  y.resize({N, cout_, g.ho, g.wo});
  const int K = cin_ * k_ * k_;
  const int rpt = g.rows_per_tile;
  const int ntiles = (g.ho + rpt - 1) / rpt;
  const int items = N * ntiles;
  const double macs = double(N) * g.ho * g.wo * K * cout_;
  const int T = macs >= kParallelMacs ? detail::max_threads() : 1;
  grow(col_, static_cast<std::size_t>(T));
  for (int t = 0; t < T; ++t) grow(col_[t], static_cast<Eigen::Index>(rpt) * g.wo * K);
  if (s_ == 2 && k_ == 3 && direct_available(1, g.wo)) {
    // Stride 2 (3 × 3): the same kernel on column-phase-split padded rows.
    const int Wp = detail::padded_width_s2(g.wo);
    pack_weights(weight_.data(), K, 1, cout_, cin_, 9, block_channels(g.wo, cout_), wpk_);
    // Rows per tile: C·(2·rows + 1)·2·Wp ≤ kTileFloats.
    const int drpt = static_cast<int>(std::clamp<long>((kTileFloats / (2L * cin_ * Wp) - 1) / 2, 1, g.ho));
    const int dtiles = (g.ho + drpt - 1) / drpt;
    for (int t = 0; t < T; ++t) grow(col_[t], static_cast<Eigen::Index>(cin_) * (2 * drpt + 1) * 2 * Wp);
#pragma omp parallel for schedule(dynamic, 1) num_threads(T) if (T > 1)
    for (int it = 0; it < N * dtiles; ++it) {
      const int n = it / dtiles;
      const int oy0 = (it % dtiles) * drpt;
      const int nrows = std::min(g.ho, oy0 + drpt) - oy0;
      const int R = 2 * (nrows - 1) + 3;
      float* xp = col_[detail::thread_id()].data();
      pad_rows_s2(x.sample(n), cin_, g.h, g.w, g.pad_left, 2 * oy0 - g.pad_top, R, Wp, xp);
      direct_tile(xp, cin_, R, Wp, 3, wpk_.data(), cout_, bias_.data(), relu_, y.sample(n), g.ho, g.wo, oy0, nrows, 2);
    }
    return;
  }
  if (direct_available(s_, g.wo)) {
    // Stride 1: "same" padding is (k−1)/2 on every side.
    const int p = (k_ - 1) / 2;
    const int Wp = padded_width(g.wo, k_);
    pack_weights(weight_.data(), K, 1, cout_, cin_, k_ * k_, block_channels(g.wo, cout_), wpk_);
    const int drpt = direct_rows_per_tile(cin_, k_, Wp, g.ho);
    const int dtiles = (g.ho + drpt - 1) / drpt;
    for (int t = 0; t < T; ++t) grow(col_[t], static_cast<Eigen::Index>(cin_) * (drpt + k_ - 1) * Wp);
#pragma omp parallel for schedule(dynamic, 1) num_threads(T) if (T > 1)
    for (int it = 0; it < N * dtiles; ++it) {
      const int n = it / dtiles;
      const int oy0 = (it % dtiles) * drpt;
      const int nrows = std::min(g.ho, oy0 + drpt) - oy0;
      const int R = nrows + k_ - 1;
      float* xp = col_[detail::thread_id()].data();
      pad_rows(x.sample(n), nullptr, cin_, g.h, g.w, p, oy0, R, Wp, xp);
      direct_tile(xp, cin_, R, Wp, k_, wpk_.data(), cout_, bias_.data(), relu_, y.sample(n), g.ho, g.wo, oy0, nrows);
    }
    return;
  }
  const CMatMap Wt(weight_.data(), K, cout_);
  const Eigen::Map<const Eigen::RowVectorXf> b(bias_.data(), cout_);
  const int plane = g.ho * g.wo;

  // One work item = one tile of one sample; items write disjoint rows of y and each is
  // computed the same way whichever thread takes it, so dynamic scheduling (robust when a
  // thread is descheduled on a shared machine) keeps the result deterministic. Inside the
  // region Eigen's GEMMs run single-threaded (it checks omp_get_num_threads()); the region
  // is entered even for a single item so that Eigen never picks its multi-threaded
  // blocking, which would change the summation order with the thread count.
#pragma omp parallel for schedule(dynamic, 1) num_threads(T) if (T > 1)
  for (int it = 0; it < items; ++it) {
    const int n = it / ntiles;
    const int oy0 = (it % ntiles) * rpt;
    const int oy1 = std::min(g.ho, oy0 + rpt);
    const int P = (oy1 - oy0) * g.wo;
    float* col = col_[detail::thread_id()].data();
    im2col(x.sample(n), g, oy0, oy1, col);
    StridedMap Y(y.sample(n) + static_cast<std::size_t>(oy0) * g.wo, P, cout_, Eigen::OuterStride<>(plane));
    Y.noalias() = CMatMap(col, P, K) * Wt;
    Y.rowwise() += b;
    if (relu_) Y = Y.cwiseMax(0.0f);
  }
}

/// What one backward() call computes and how its work is split (derived from the shapes only).
struct Conv2d::BackwardPlan {
  int N, K, Kf, rpt, ntiles, plane, T, Wp, groups, fpad_top, fpad_left;
  std::size_t dy_sample;
  bool flip, direct, by_sample, direct_dw, shared_col;
};

void Conv2d::backward(const Tensor& x, const Tensor& y, const Tensor& dy, Tensor* dx) {
  const Geometry g = geometry(x.shape());
  const int N = x.n();
  require_shape(dy.shape(), {N, cout_, g.ho, g.wo}, "Conv2d::backward dy");
  require_shape(y.shape(), dy.shape(), "Conv2d::backward y");
  if (dx != nullptr) dx->resize(x.shape());
  const BackwardPlan b = backward_plan(g, N, dx != nullptr);
  prepare_backward(b, g, y, dy, dx);
#pragma omp parallel for schedule(dynamic, 1) num_threads(b.T) if (b.T > 1)
  for (int q = 0; q < b.groups; ++q) backward_group(b, g, q, x, y, dy, dx);
  reduce_backward(b, g, dx);
}

Conv2d::BackwardPlan Conv2d::backward_plan(const Geometry& g, int N, bool has_dx) const {
  BackwardPlan b{};
  b.N = N;
  b.K = cin_ * k_ * k_;
  b.Kf = cout_ * k_ * k_;  // patch length of dY for the stride-1 dX
  b.rpt = g.rows_per_tile;
  b.ntiles = (g.ho + b.rpt - 1) / b.rpt;
  b.plane = g.ho * g.wo;
  b.dy_sample = static_cast<std::size_t>(cout_) * b.plane;
  const double macs = double(N) * g.ho * g.wo * b.K * cout_;
  b.T = macs >= kParallelMacs ? detail::max_threads() : 1;
  // dX. For stride 1 it is itself a "same" convolution of dY with the kernel flipped in
  // space and transposed in channels, padded by k−1−pt (= pt for odd k):
  //   dx[c, iy, ix] = Σ_{o, ky', kx'} Wf[(o, ky', kx'), c] · dy[o, iy + ky' − pt, ix + kx' − pl],
  //   Wf[(o, ky', kx'), c] = w[o, c, k−1−ky', k−1−kx'],
  // so each dX tile is one GEMM (P × Cout·k²)·(Cout·k² × Cin) written in place: no dX_col of
  // P × Cin·k² and no scatter. Other strides use dX_col = dY·W and col2im.
  b.flip = s_ == 1;
  b.direct = b.flip && has_dx && direct_available(s_, g.wo);
  b.Wp = padded_width(g.wo, k_);
  b.by_sample = N >= 2;
  // dW directly from a padded copy of the whole sample (3 × 3, stride 1, a batch).
  b.direct_dw = b.flip && k_ == 3 && b.by_sample && direct_available(s_, g.wo);
  // Work split into groups, each with its own dW/db accumulator; groups are summed in
  // group order afterwards. A batch (N ≥ 2) is cut into ≤ 16 runs of consecutive
  // samples; a single sample into its row tiles. The grouping depends on N only, and
  // each group is computed identically by whichever thread takes it, so the result is
  // deterministic for any thread count, and dynamic scheduling lets a running thread take
  // over the work of a descheduled one. For a single sample with stride ≠ 1 the tiles
  // write dX_col rows of one shared P × K buffer and col2im runs once afterwards.
  b.groups = b.by_sample ? std::min(N, 16) : b.ntiles;
  b.shared_col = has_dx && !b.by_sample && !b.flip;
  b.fpad_top = k_ - 1 - g.pad_top;
  b.fpad_left = k_ - 1 - g.pad_left;
  return b;
}

void Conv2d::prepare_backward(const BackwardPlan& b, const Geometry& g, const Tensor& y, const Tensor& dy,
                              Tensor* dx) {
  const int T = b.T;
  grow(col_, static_cast<std::size_t>(T));
  grow(dyr_, static_cast<std::size_t>(T));
  grow(dw_, static_cast<std::size_t>(b.groups));
  grow(db_, static_cast<std::size_t>(b.groups));
  if (b.direct) grow(pad_, static_cast<std::size_t>(T));
  for (int t = 0; t < T; ++t) {
    grow(col_[t], static_cast<Eigen::Index>(b.rpt) * g.wo * std::max(b.K, b.flip && !b.direct ? b.Kf : 0));
    if (b.direct) grow(pad_[t], static_cast<Eigen::Index>(cout_) * (b.rpt + k_ - 1) * b.Wp);
    if (b.direct_dw) {
      grow(xpad_, static_cast<std::size_t>(T));
      grow(dyz_, static_cast<std::size_t>(T));
      grow(xpad_[t], static_cast<Eigen::Index>(cin_) * (g.h + 2) * b.Wp);
      grow(dyz_[t], static_cast<Eigen::Index>(cout_) * (g.ho + 2) * b.Wp);
    }
    if (relu_ && b.by_sample) grow(dyr_[t], static_cast<Eigen::Index>(b.dy_sample));
  }
  for (int q = 0; q < b.groups; ++q) {
    dw_[q].setZero(b.K, cout_);
    db_[q].setZero(cout_);
  }
  if (b.shared_col) grow(dxcol_, static_cast<Eigen::Index>(b.plane) * b.K);
  if (dx != nullptr && !b.flip && b.by_sample) dx->set_zero();
  // d/dz relu(z) = [y > 0]: dY is masked once per sample (it is read by neighbouring
  // tiles of the stride-1 dX). For a single sample, mask it before the tiles start.
  if (relu_ && !b.by_sample) {
    grow(dymask_, static_cast<Eigen::Index>(dy.size()));
    dymask_.head(static_cast<Eigen::Index>(dy.size())) = (y.flat().array() > 0.0f).select(dy.flat(), 0.0f);
  }
  if (b.flip && dx != nullptr) {
    wflip_.resize(b.Kf, cin_);
    for (int o = 0; o < cout_; ++o)
      for (int c = 0; c < cin_; ++c)
        for (int ky = 0; ky < k_; ++ky)
          for (int kx = 0; kx < k_; ++kx)
            wflip_((o * k_ + (k_ - 1 - ky)) * k_ + (k_ - 1 - kx), c) = weight_(o, c, ky, kx);
    if (b.direct) pack_weights(wflip_.data(), b.Kf, 1, cin_, cout_, k_ * k_, block_channels(g.wo, cin_), wpkf_);
  }
}

// dL/dz of sample n, [Cout, Ho, Wo]: dY masked by the fused ReLU (into thread tid's buffer
// for a batch; the mask made by prepare_backward for a single sample).
const float* Conv2d::masked_dy(const BackwardPlan& b, int n, int tid, const Tensor& y, const Tensor& dy) {
  const float* gs = dy.sample(n);
  if (relu_ && b.by_sample) {
    float* m = dyr_[tid].data();
    const float* ys = y.sample(n);
    for (std::size_t i = 0; i < b.dy_sample; ++i) m[i] = ys[i] > 0.0f ? gs[i] : 0.0f;
    return m;
  }
  if (relu_) return dymask_.data();
  return gs;
}

// Group q: samples [n_lo, n_hi) with all tiles, or tile q of sample 0.
void Conv2d::backward_group(const BackwardPlan& b, const Geometry& g, int q, const Tensor& x, const Tensor& y,
                            const Tensor& dy, Tensor* dx) {
  const int tid = detail::thread_id();
  const int N = b.N;
  const int n_lo = b.by_sample ? static_cast<int>(static_cast<long>(N) * q / b.groups) : 0;
  const int n_hi = b.by_sample ? static_cast<int>(static_cast<long>(N) * (q + 1) / b.groups) : 1;
  for (int n = n_lo; n < n_hi; ++n) {
    const float* gs = masked_dy(b, n, tid, y, dy);
    float* dxs = dx == nullptr ? nullptr : dx->sample(n);
    if (b.direct_dw) {
      backward_sample_direct(b, g, q, n, x, gs, dxs);
    } else {
      backward_tiles(b, g, q, n, b.by_sample ? 0 : q, b.by_sample ? b.ntiles : q + 1, x, gs, dxs);
    }
  }
}

// dW, db and dX of sample n by the direct kernels (3 × 3, stride 1).
void Conv2d::backward_sample_direct(const BackwardPlan& b, const Geometry& g, int q, int n, const Tensor& x,
                                    const float* gs, float* dxs) {
  const int tid = detail::thread_id();
  const int Wp = b.Wp, plane = b.plane;
  float* xp = xpad_[tid].data();
  float* dz = dyz_[tid].data();
  // Padded x and dY of the whole sample (p = 1): dY's padding leaves zero lanes
  // beyond Wo (Wp = VB·16 + 2), as direct_dw3 needs; the same buffer feeds dX.
  pad_rows(x.sample(n), nullptr, cin_, g.h, g.w, 1, 0, g.h + 2, Wp, xp);
  pad_rows(gs, nullptr, cout_, g.ho, g.wo, 1, 0, g.ho + 2, Wp, dz);
  direct_dw_sample(xp, cin_, Wp, dz + Wp + 1, static_cast<long>(g.ho + 2) * Wp, Wp, cout_, g.ho, g.wo, dw_[q].data());
  db_[q].noalias() += CStridedMap(gs, plane, cout_, Eigen::OuterStride<>(plane)).colwise().sum().transpose();
  if (dxs != nullptr) direct_tile(dz, cout_, g.ho + 2, Wp, k_, wpkf_.data(), cin_, nullptr, false, dxs, g.h, g.w, 0, g.h);
}

// dW, db (im2col + GEMM) and dX of the row tiles [t_lo, t_hi) of sample n.
void Conv2d::backward_tiles(const BackwardPlan& b, const Geometry& g, int q, int n, int t_lo, int t_hi,
                            const Tensor& x, const float* gs, float* dxs) {
  const int tid = detail::thread_id();
  const int K = b.K, plane = b.plane, rpt = b.rpt;
  Eigen::MatrixXf& dW = dw_[q];
  Eigen::VectorXf& db = db_[q];
  float* col = col_[tid].data();
  const CMatMap Wt(weight_.data(), K, cout_);
  for (int tile = t_lo; tile < t_hi; ++tile) {
    const int oy0 = tile * rpt;
    const int oy1 = std::min(g.ho, oy0 + rpt);
    const int P = (oy1 - oy0) * g.wo;
    const std::size_t off = static_cast<std::size_t>(oy0) * g.wo;
    CStridedMap G(gs + off, P, cout_, Eigen::OuterStride<>(plane));
    MatMap C(col, P, K);
    im2col(x.sample(n), g, oy0, oy1, col);
    dW.noalias() += C.transpose() * G;
    db.noalias() += G.colwise().sum().transpose();
    if (dxs == nullptr) continue;
    if (b.direct) {
      // dX rows [oy0, oy1) from dY rows [oy0 − p, oy1 + p): the same direct kernel.
      const int R = (oy1 - oy0) + k_ - 1;
      float* dyp = pad_[tid].data();
      pad_rows(gs, nullptr, cout_, g.ho, g.wo, b.fpad_top, oy0, R, b.Wp, dyp);
      direct_tile(dyp, cout_, R, b.Wp, k_, wpkf_.data(), cin_, nullptr, false, dxs, g.h, g.w, oy0, oy1 - oy0);
    } else if (b.flip) {
      // Input rows [oy0, oy1) (stride 1: the input grid is the output grid).
      im2col_planes(gs, cout_, g.ho, g.wo, k_, 1, b.fpad_top, b.fpad_left, g.w, oy0, oy1, col);
      StridedMap DX(dxs + off, P, cin_, Eigen::OuterStride<>(g.h * g.w));
      DX.noalias() = MatMap(col, P, b.Kf) * wflip_;
    } else if (b.shared_col) {
      StridedMap(dxcol_.data() + off, P, K, Eigen::OuterStride<>(plane)).noalias() = G * Wt.transpose();
    } else {
      C.noalias() = G * Wt.transpose();
      col2im(col, g, oy0, oy1, dxs);
    }
  }
}

void Conv2d::reduce_backward(const BackwardPlan& b, const Geometry& g, Tensor* dx) {
  if (b.shared_col) {
    dx->set_zero();
    col2im(dxcol_.data(), g, 0, g.ho, dx->data());
  }
  // Fixed-order reduction over groups.
  MatMap dWt(dweight_.data(), b.K, cout_);
  Eigen::Map<Eigen::VectorXf> dB(dbias_.data(), cout_);
  dWt = dw_[0];
  dB = db_[0];
  for (int q = 1; q < b.groups; ++q) {
    dWt += dw_[q];
    dB += db_[q];
  }
}

std::vector<ParamRef> Conv2d::parameters() {
  return {{"weight", &weight_, &dweight_, true}, {"bias", &bias_, &dbias_, false}};
}

void Conv2d::initialize(const Initializer& init, Rng& rng) {
  init.fill(weight_, cin_ * k_ * k_, cout_ * k_ * k_, rng);
  bias_.set_zero();
}

}  // namespace dc
