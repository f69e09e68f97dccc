#include "dc/learning/inference_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ctime>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "dc/core/error.hpp"
#include "dc/learning/layers/conv2d.hpp"
#include "layers/conv_direct.hpp"
#include "omp_util.hpp"

namespace dc {

namespace {

/// CPU time of the calling thread [ms] (per-step profiling on a shared machine).
double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

/// Whether the direct kernels serve this conv (see Conv2d::forward's dispatch).
bool direct_conv(int k, int stride, int wo) {
  if (!detail::direct_available(1, wo)) return false;
  return stride == 1 || (stride == 2 && k == 3);
}

#if defined(__AVX512F__)
/// Lanes l with lo ≤ l < hi (clamped to [0, 16]).
__mmask16 lane_mask(int lo, int hi) {
  lo = std::clamp(lo, 0, 16);
  hi = std::clamp(hi, lo, 16);
  const unsigned bits = (hi == 16 ? 0xFFFFu : (1u << hi) - 1u) & ~((1u << lo) - 1u);
  return static_cast<__mmask16>(bits);
}

/// Columns ix0 … ix0 + 15 of one (virtual) input row of width w, zero outside [0, w).
/// `row` is the source row: the plane's row iy, or iy/2 through a nearest upsampling
/// (column ix reads row[ix/2]). Standardised lanes are (v − mean)·inv, as ChannelStats::apply.
__m512 source_vector(const float* row, int ix0, int w, bool up, bool standardise, float mean, float inv) {
  const __mmask16 valid = lane_mask(-ix0, w - ix0);
  __m512 v;
  if (!up) {
    v = _mm512_maskz_loadu_ps(valid, row + ix0);
  } else {
    // Lane l reads source column ⌊(ix0 + l)/2⌋ = sbase + ((ix0 − 2·sbase + l) >> 1).
    const int sbase = detail::floor_div(ix0, 2);
    const int sw = (w + 1) / 2;  // source width: w = 2·sw or 2·sw − 1
    const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512 s = _mm512_maskz_loadu_ps(lane_mask(-sbase, sw - sbase), row + sbase);
    const __m512i idx = _mm512_srai_epi32(_mm512_add_epi32(iota, _mm512_set1_epi32(ix0 - 2 * sbase)), 1);
    v = _mm512_maskz_mov_ps(valid, _mm512_permutexvar_ps(idx, s));
  }
  if (standardise) v = _mm512_maskz_mul_ps(valid, _mm512_sub_ps(v, _mm512_set1_ps(mean)), _mm512_set1_ps(inv));
  return v;
}
#endif

}  // namespace

InferencePlan::InferencePlan(Network& net, const ChannelStats& input_stats)
    : net_(&net), stats_(input_stats), in_(net.input_shape()), out_shape_(net.output_shape()) {
  if (stats_.channels() != in_.c || stats_.std.size() != stats_.mean.size())
    throw InvalidArgument("InferencePlan: the input statistics have " + std::to_string(stats_.channels()) +
                          " channels, the network reads " + std::to_string(in_.c));
  if (!compile(net)) {
    steps_.clear();
    act_.clear();
  }
}

// Classifies the graph (conv and upsample nodes only, upsamples of the input or a conv read
// by convs alone, a conv last) and builds one Step per conv with its weights packed.
bool InferencePlan::compile(Network& net) {
#if !defined(__AVX512F__)
  (void)net;
  return false;
#else
  const std::size_t n = net.size();
  std::vector<char> conv(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::string type = net.layer(i).type();
    const std::vector<int>& ins = net.node_inputs(i);
    if (type == "conv") {
      conv[i] = 1;
    } else if (type != "upsample" || ins.size() != 1 || (ins[0] >= 0 && !conv[static_cast<std::size_t>(ins[0])])) {
      return false;
    }
  }
  if (!conv[n - 1]) return false;
  for (std::size_t i = 0; i < n; ++i)  // every upsample is read by convs only
    for (const int j : net.node_inputs(i))
      if (j >= 0 && !conv[static_cast<std::size_t>(j)] && !conv[i]) return false;
  act_.assign(n, Tensor());
  std::size_t pad_floats = 0, block_floats = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!conv[i]) continue;
    auto& layer = dynamic_cast<Conv2d&>(net.layer(i));
    Step s;
    s.node = static_cast<int>(i);
    s.cin = layer.in_channels();
    s.cout = layer.out_channels();
    s.k = layer.kernel();
    s.stride = layer.stride();
    s.relu = layer.relu();
    s.sparse = i + 1 == n && s.k == 1 && s.stride == 1;
    const int first = net.node_inputs(i)[0];
    const Shape x = first < 0 ? in_ : net.node_shape(static_cast<std::size_t>(first));
    s.h = x.h;
    s.w = x.w;
    s.ho = net.node_shape(i).h;
    s.wo = net.node_shape(i).w;
    if (!s.sparse && !direct_conv(s.k, s.stride, s.wo)) return false;
    // "same" padding as Conv2d: total max((Ho−1)·s + k − H, 0), the smaller half before.
    s.pad_top = std::max((s.ho - 1) * s.stride + s.k - s.h, 0) / 2;
    s.pad_left = std::max((s.wo - 1) * s.stride + s.k - s.w, 0) / 2;
    for (const int j : net.node_inputs(i)) {
      const bool up = j >= 0 && !conv[static_cast<std::size_t>(j)];
      const int from = up ? net.node_inputs(static_cast<std::size_t>(j))[0] : j;
      const Shape p = from < 0 ? in_ : net.node_shape(static_cast<std::size_t>(from));
      for (int c = 0; c < p.c; ++c) {
        Source src{from, c, p.h, p.w, up, from < 0, 0.0f, 1.0f};
        if (from < 0) {
          src.mean = stats_.mean[static_cast<std::size_t>(c)];
          src.inv = 1.0f / stats_.std[static_cast<std::size_t>(c)];
        }
        s.src.push_back(src);
      }
    }
    if (static_cast<int>(s.src.size()) != s.cin) return false;
    const int K = s.cin * s.k * s.k;
    s.bias.assign(layer.bias().data(), layer.bias().data() + s.cout);
    if (s.sparse) {
      s.weight.assign(layer.weight().data(), layer.weight().data() + static_cast<std::size_t>(s.cout) * s.cin);
      block_floats = std::max(block_floats, static_cast<std::size_t>(s.cin) * detail::kLanes);
      if (s.ho != s.h || s.wo != s.w) return false;  // a 1×1 stride-1 conv keeps the size
      for (const Source& src : s.src)  // full-size planes, or upsampled ones of ⌈W/2⌉ columns
        if (src.w != (src.up ? (s.w + 1) / 2 : s.w)) return false;
    } else {
      detail::pack_weights(layer.weight().data(), K, 1, s.cout, s.cin, s.k * s.k, detail::block_channels(s.wo, s.cout),
                           s.weight);
      const bool s2 = s.stride == 2;
      s.rows = s2 ? 2 * (s.ho - 1) + 3 : s.ho + s.k - 1;
      s.pitch = s2 ? detail::padded_width_s2(s.wo) : detail::padded_width(s.wo, s.k);
      pad_floats = std::max(pad_floats, static_cast<std::size_t>(s.cin) * s.rows * s.pitch * (s2 ? 2 : 1));
      act_[i] = Tensor(1, s.cout, s.ho, s.wo);
    }
    steps_.push_back(std::move(s));
  }
  pad_.assign(pad_floats, 0.0f);
  block_.assign(block_floats, 0.0f);
  bases_.assign(block_floats / detail::kLanes, nullptr);
  out_ = Tensor(out_shape_);
  return true;
#endif
}

const float* InferencePlan::plane(const Source& src, const Tensor& x) const {
  const float* base = src.node < 0 ? x.data() : act_[static_cast<std::size_t>(src.node)].data();
  return base + static_cast<std::size_t>(src.channel) * src.h * src.w;
}

// Gathers the step's padded input rows (concatenation, upsampling and standardisation
// included) into pad_ exactly as pad_rows / pad_rows_s2 lay them out for Conv2d, then runs
// the same direct kernel over all output rows at once.
void InferencePlan::run_dense(const Step& s, const Tensor& x) {
#if defined(__AVX512F__)
  using detail::kLanes;
  float* xp = pad_.data();
  const int R = s.rows, Wp = s.pitch;
  const __m512i even = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
  const __m512i odd = _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
  for (int c = 0; c < s.cin; ++c) {
    const Source& src = s.src[static_cast<std::size_t>(c)];
    const float* base = plane(src, x);
    for (int r = 0; r < R; ++r) {
      const int iy = r - s.pad_top;  // (virtual) input row of padded row r
      if (s.stride == 1) {
        float* dst = xp + (static_cast<std::size_t>(c) * R + r) * Wp;
        if (iy < 0 || iy >= s.h) {
          std::memset(dst, 0, sizeof(float) * Wp);
          continue;
        }
        const float* row = base + static_cast<std::size_t>(src.up ? iy / 2 : iy) * src.w;
        for (int i0 = 0; i0 < Wp; i0 += kLanes) {
          const __m512 v = source_vector(row, i0 - s.pad_left, s.w, src.up, src.standardise, src.mean, src.inv);
          _mm512_mask_storeu_ps(dst + i0, lane_mask(0, Wp - i0), v);
        }
        continue;
      }
      // Stride 2: phase φ, index i = input column 2i + φ − pl.
      float* dst = xp + (static_cast<std::size_t>(c) * R + r) * 2 * Wp;
      if (iy < 0 || iy >= s.h) {
        std::memset(dst, 0, sizeof(float) * 2 * Wp);
        continue;
      }
      const float* row = base + static_cast<std::size_t>(src.up ? iy / 2 : iy) * src.w;
      for (int i0 = 0; i0 < Wp; i0 += kLanes) {
        const int ix0 = 2 * i0 - s.pad_left;
        const __m512 a = source_vector(row, ix0, s.w, src.up, src.standardise, src.mean, src.inv);
        const __m512 b = source_vector(row, ix0 + kLanes, s.w, src.up, src.standardise, src.mean, src.inv);
        const __mmask16 m = lane_mask(0, Wp - i0);
        _mm512_mask_storeu_ps(dst + i0, m, _mm512_permutex2var_ps(a, even, b));
        _mm512_mask_storeu_ps(dst + Wp + i0, m, _mm512_permutex2var_ps(a, odd, b));
      }
    }
  }
  detail::direct_tile(xp, s.cin, R, Wp, s.k, s.weight.data(), s.cout, s.bias.data(), s.relu,
                      act_[static_cast<std::size_t>(s.node)].data(), s.ho, s.wo, 0, s.ho, s.stride);
#else
  (void)s, (void)x;
#endif
}

// The 1×1 head at the listed pixels: Network::forward_at's loop (blocks of 16 pixels,
// channel-major, fused multiply-adds over the channels from 0, then + bias, then ReLU).
void InferencePlan::run_sparse(const Step& s, const Tensor& x, std::span<const int> pixels) {
  const int W = out_shape_.w, P = out_shape_.h * out_shape_.w;
  for (const int p : pixels)
    if (p < 0 || p >= P) throw InvalidArgument("InferencePlan::run: pixel " + std::to_string(p) + " outside the output");
  constexpr int kB = detail::kLanes;
  const int cin = s.cin;
  float* v = block_.data();
  float acc[kB];
  int full[kB], half[kB];  // offsets of the block's pixels in a full-size and an upsampled plane
  for (int c = 0; c < cin; ++c) bases_[static_cast<std::size_t>(c)] = plane(s.src[static_cast<std::size_t>(c)], x);
  for (std::size_t p0 = 0; p0 < pixels.size(); p0 += kB) {
    const int nb = static_cast<int>(std::min<std::size_t>(kB, pixels.size() - p0));
    for (int b = 0; b < kB; ++b) {
      const int p = pixels[p0 + static_cast<std::size_t>(std::min(b, nb - 1))];
      const int Y = p / W, X = p % W;
      full[b] = p;
      half[b] = (Y / 2) * ((W + 1) / 2) + X / 2;
    }
    for (int c = 0; c < cin; ++c) {
      const Source& src = s.src[static_cast<std::size_t>(c)];
      const float* base = bases_[static_cast<std::size_t>(c)];
      float* vc = v + static_cast<std::size_t>(c) * kB;
      const int* at = src.up ? half : full;
      if (src.standardise) {
        for (int b = 0; b < kB; ++b) vc[b] = (base[at[b]] - src.mean) * src.inv;
      } else {
        for (int b = 0; b < kB; ++b) vc[b] = base[at[b]];
      }
    }
    for (int o = 0; o < s.cout; ++o) {
      const float* wo = s.weight.data() + static_cast<std::size_t>(o) * cin;
      for (int b = 0; b < kB; ++b) acc[b] = 0.0f;
      for (int c = 0; c < cin; ++c) {
        const float w = wo[c];
        const float* vc = v + static_cast<std::size_t>(c) * kB;
        for (int b = 0; b < kB; ++b) acc[b] = std::fma(w, vc[b], acc[b]);
      }
      float* yo = out_.data() + static_cast<std::size_t>(o) * P;
      for (int b = 0; b < nb; ++b) {
        float r = acc[b] + s.bias[static_cast<std::size_t>(o)];
        if (s.relu) r = std::max(r, 0.0f);
        yo[pixels[p0 + static_cast<std::size_t>(b)]] = r;
      }
    }
  }
}

const Tensor& InferencePlan::run(const Tensor& features, std::span<const int> pixels, std::vector<double>* step_ms) {
  require_shape(features.shape(), in_, "InferencePlan::run input");
  if (step_ms) step_ms->assign(step_count(), 0.0);
  if (!fused()) {
    const double t0 = step_ms ? thread_cpu_ms() : 0.0;
    scratch_ = features;
    stats_.apply(scratch_);
    net_->forward_at(scratch_, pixels, out_);
    if (step_ms) (*step_ms)[0] = thread_cpu_ms() - t0;
    return out_;
  }
  for (std::size_t i = 0; i < steps_.size(); ++i) {
    const double t0 = step_ms ? thread_cpu_ms() : 0.0;
    const Step& s = steps_[i];
    if (s.sparse) {
      run_sparse(s, features, pixels);
    } else {
      run_dense(s, features);
    }
    if (step_ms) (*step_ms)[i] = thread_cpu_ms() - t0;
  }
  return steps_.back().sparse ? out_ : act_.back();
}

std::string InferencePlan::step_name(std::size_t i) const {
  if (!fused()) return "network";
  return net_->node_name(static_cast<std::size_t>(steps_.at(i).node));
}

}  // namespace dc
