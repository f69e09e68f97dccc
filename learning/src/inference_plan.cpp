#include "dc/learning/inference_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "dc/core/error.hpp"
#include "dc/learning/layers/conv2d.hpp"
#include "layers/conv_direct.hpp"
#include "omp_util.hpp"
#include "thread_cpu_time.hpp"

namespace dc {

namespace {

/// Whether the direct kernels serve this conv (see Conv2d::forward's dispatch).
bool direct_conv(int k, int stride, int wo) {
  if (!detail::direct_available(1, wo)) return false;
  return stride == 1 || (stride == 2 && k == 3);
}

/// Bits l of lanes lo ≤ l < hi (clamped to [0, 16]).
unsigned lane_bits(int lo, int hi) {
  lo = std::clamp(lo, 0, 16);
  hi = std::clamp(hi, lo, 16);
  return ((1u << hi) - 1u) & ~((1u << lo) - 1u);
}

#if defined(__AVX512F__)
/// Lanes l with lo ≤ l < hi (clamped to [0, 16]).
[[gnu::always_inline]] inline __mmask16 lane_mask(int lo, int hi) {
  lo = std::clamp(lo, 0, 16);
  hi = std::clamp(hi, lo, 16);
  return static_cast<__mmask16>(((1u << hi) - 1u) & ~((1u << lo) - 1u));
}

/// The lanes of one gathered vector (Columns) from one (virtual) input row, zero outside
/// the row. `row` is the source row: the plane's row iy, or with UP its row iy/2 read through
/// a nearest upsampling (column ix reads row[ix/2]). With STD the lanes are standardised,
/// (v − mean)·inv, the operations of ChannelStats::apply.
template <bool UP, bool STD>
[[gnu::always_inline]] inline __m512 source_vector(const float* row, const InferencePlan::Columns& col, __m512 mean,
                                                   __m512 inv) {
  const auto valid = static_cast<__mmask16>(col.valid);
  __m512 v;
  if constexpr (!UP) {
    v = _mm512_maskz_loadu_ps(valid, row + col.ix0);
  } else {
    const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512 src = _mm512_maskz_loadu_ps(static_cast<__mmask16>(col.up_valid), row + col.sbase);
    const __m512i idx = _mm512_srai_epi32(_mm512_add_epi32(iota, _mm512_set1_epi32(col.shift)), 1);
    v = _mm512_maskz_mov_ps(valid, _mm512_permutexvar_ps(idx, src));
  }
  if constexpr (STD) v = _mm512_maskz_mul_ps(valid, _mm512_sub_ps(v, mean), inv);
  return v;
}

/// Where one input channel comes from and how the kernel's buffer is laid out.
struct Gather {
  const float* base;  ///< source plane
  int src_pitch;      ///< its row pitch
  int h, w;           ///< the (virtual) input size
  int pad_top, pad_left;
  int R, pitch;       ///< padded rows (flat stride 2: rows per phase plane) and row pitch
  float mean, inv;    ///< standardisation
  int pr0, pr1;       ///< the padded rows [pr0, pr1) to gather
};

/// One input channel's padded input for the kernel, zero outside the image. Layout 0 (stride
/// 1, rows or flat): [R][pitch], column p + ix = input column ix, padded row r = input row
/// r − pad_top (pad_rows). Layout 1 (stride 2, rows): [R][2][pitch], phase φ index i = input
/// column 2i + φ − pl (pad_rows_s2). Layout 2 (stride 2, flat): four planes (ρ, φ) of
/// [R][pitch], element (i, j) = padded row 2i + ρ, padded column 2j + φ. Every layout gathers
/// the padded rows [pr0, pr1) only; layouts 0 and 1 from xp's first row (= padded row pr0),
/// layout 2 at their places in the phase planes.
template <bool UP, bool STD>
void gather_channel(const Gather& g, const std::vector<InferencePlan::Columns>& cols, int layout, float* xp) {
  using detail::kLanes;
  const __m512 mean = _mm512_set1_ps(g.mean), inv = _mm512_set1_ps(g.inv);
  const __m512i even = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
  const __m512i odd = _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
  const int Wp = g.pitch;
  const long phase = static_cast<long>(g.R) * Wp;  // layout 2
  const int first = g.pr0, rows = g.pr1;
  for (int pr = first; pr < rows; ++pr) {  // padded row
    float* d0 = layout == 2 ? xp + (pr % 2) * 2 * phase + static_cast<long>(pr / 2) * Wp
                            : xp + static_cast<long>(pr - first) * Wp * (layout == 1 ? 2 : 1);
    float* d1 = layout == 2 ? d0 + phase : d0 + Wp;  // odd phase (stride 2)
    const int iy = pr - g.pad_top;
    if (iy < 0 || iy >= g.h) {
      std::memset(d0, 0, sizeof(float) * Wp);
      if (layout != 0) std::memset(d1, 0, sizeof(float) * Wp);
      continue;
    }
    const float* row = g.base + static_cast<std::size_t>(UP ? iy / 2 : iy) * g.src_pitch;
    const InferencePlan::Columns* col = cols.data();
    if (layout == 0) {
      for (int i0 = 0; i0 < Wp; i0 += kLanes, ++col)
        _mm512_mask_storeu_ps(d0 + i0, lane_mask(0, Wp - i0), source_vector<UP, STD>(row, *col, mean, inv));
      continue;
    }
    for (int i0 = 0; i0 < Wp; i0 += kLanes, col += 2) {
      const __m512 a = source_vector<UP, STD>(row, col[0], mean, inv);
      const __m512 b = source_vector<UP, STD>(row, col[1], mean, inv);
      const __mmask16 m = lane_mask(0, Wp - i0);
      _mm512_mask_storeu_ps(d0 + i0, m, _mm512_permutex2var_ps(a, even, b));
      _mm512_mask_storeu_ps(d1 + i0, m, _mm512_permutex2var_ps(a, odd, b));
    }
  }
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
// by convs alone, a conv last) and builds one Step per conv (add_step).
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
  tmpl_rows_.assign(n, {});
  need_rows_.assign(n, {});
  comp_rows_.assign(n, {});
  for (std::size_t i = 0; i < n; ++i)  // every upsample is read by convs only
    for (const int j : net.node_inputs(i))
      if (j >= 0 && !conv[static_cast<std::size_t>(j)] && !conv[i]) return false;
  // Nodes the last node reads (directly or through an upsampling) keep the plain layout:
  // the sparse head indexes their planes as H × W.
  std::vector<char> head_reads(n, 0);
  for (const int j : net.node_inputs(n - 1)) {
    if (j < 0) continue;
    const int from = conv[static_cast<std::size_t>(j)] ? j : net.node_inputs(static_cast<std::size_t>(j))[0];
    if (from >= 0) head_reads[static_cast<std::size_t>(from)] = 1;
  }
  act_.assign(n, Tensor());
  pad_.clear();
  block_.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (conv[i] && !add_step(net, i, conv, head_reads[i] != 0)) return false;
  bases_.assign(block_.size() / detail::kLanes, nullptr);
  out_ = Tensor(out_shape_);
  calibrate_templates();
  return true;
#endif
}

bool InferencePlan::add_step(Network& net, std::size_t i, const std::vector<char>& conv, bool plain_layout) {
  auto& layer = dynamic_cast<Conv2d&>(net.layer(i));
  Step s;
  s.node = static_cast<int>(i);
  s.cin = layer.in_channels();
  s.cout = layer.out_channels();
  s.k = layer.kernel();
  s.stride = layer.stride();
  s.relu = layer.relu();
  s.sparse = i + 1 == net.size() && s.k == 1 && s.stride == 1;
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
    if (std::find(s.inputs.begin(), s.inputs.end(), std::pair{from, up}) == s.inputs.end()) s.inputs.emplace_back(from, up);
    const Shape p = from < 0 ? in_ : net.node_shape(static_cast<std::size_t>(from));
    const Shape stored = from < 0 ? in_ : act_[static_cast<std::size_t>(from)].shape();  // its layout
    for (int c = 0; c < p.c; ++c) {
      Source src{from, c, p.h, p.w, stored.w, static_cast<long>(stored.plane()), up, from < 0, 0.0f, 1.0f};
      if (from < 0) {
        src.mean = stats_.mean[static_cast<std::size_t>(c)];
        src.inv = 1.0f / stats_.std[static_cast<std::size_t>(c)];
      }
      s.src.push_back(src);
    }
  }
  if (static_cast<int>(s.src.size()) != s.cin) return false;
  s.bias.assign(layer.bias().data(), layer.bias().data() + s.cout);
  if (s.sparse) {
    s.weight.assign(layer.weight().data(), layer.weight().data() + static_cast<std::size_t>(s.cout) * s.cin);
    block_.resize(std::max(block_.size(), static_cast<std::size_t>(s.cin) * detail::kLanes));
    if (s.ho != s.h || s.wo != s.w) return false;  // a 1 × 1 stride-1 conv keeps the size
    for (const Source& src : s.src)  // full-size planes, or upsampled ones of ⌈W/2⌉ columns
      if (src.pitch != (src.up ? (s.w + 1) / 2 : s.w) || src.w != src.pitch) return false;
  } else {
    layout_dense(s, layer, plain_layout);
  }
  steps_.push_back(std::move(s));
  return true;
}

// Row layout (direct_tile: each output row in whole vectors) or, where that would leave most
// lanes idle, the flat layout (direct_flat: the output plane as one run of pitch Wq).
void InferencePlan::layout_dense(Step& s, Conv2d& layer, bool plain_layout) {
  const bool s2 = s.stride == 2;
  const int wq = s.wo + (s2 ? 1 : s.k - 1);  // flat row pitch: the output row plus its halo
  const int row_lanes = s.ho * detail::vec_count(s.wo) * detail::kLanes;
  const int flat_lanes = detail::vec_count(s.ho * wq) * detail::kLanes;
  s.flat = !plain_layout && 5 * flat_lanes <= 4 * row_lanes;
  const int K = s.cin * s.k * s.k;
  const int ob = s.flat ? detail::flat_block_channels(s.cout) : detail::block_channels(s.wo, s.cout);
  detail::pack_weights(layer.weight().data(), K, 1, s.cout, s.cin, s.k * s.k, ob, s.weight);
  std::size_t floats = 0;
  if (s.flat) {
    s.pitch = wq;
    // Stride 1: padded rows r = input row r − p; stride 2: four phase planes (ρ, φ) of
    // (Ho + 1) rows, element (i, j) = padded (2i + ρ, 2j + φ).
    s.rows = s2 ? s.ho + 1 : s.ho + s.k - 1;
    const long phase = static_cast<long>(s.rows) * wq;
    s.x_plane = s2 ? 4 * phase : phase;
    s.off.clear();
    for (int ky = 0; ky < s.k; ++ky)
      for (int kx = 0; kx < s.k; ++kx)
        s.off.push_back(s2 ? static_cast<int>(((ky % 2) * 2 + kx % 2) * phase) + (ky / 2) * wq + kx / 2 : ky * wq + kx);
    // The kernel reads whole vectors past the last channel's plane (don't-care lanes).
    // A run starting at t0 = a·Wq (run_dense) reads up to 15 lanes further: one more vector.
    floats = static_cast<std::size_t>(s.cin * s.x_plane + *std::max_element(s.off.begin(), s.off.end()) +
                                      (detail::vec_count(s.ho * wq) + 1) * detail::kLanes);
    act_[static_cast<std::size_t>(s.node)] = Tensor(1, s.cout, s.ho, wq);
  } else {
    s.rows = s2 ? 2 * (s.ho - 1) + 3 : s.ho + s.k - 1;
    s.pitch = s2 ? detail::padded_width_s2(s.wo) : detail::padded_width(s.wo, s.k);
    s.x_plane = static_cast<long>(s.rows) * s.pitch * s.stride;
    floats = static_cast<std::size_t>(s.cin * s.x_plane);
    act_[static_cast<std::size_t>(s.node)] = Tensor(1, s.cout, s.ho, s.wo);
  }
  tmpl_rows_[static_cast<std::size_t>(s.node)].assign(static_cast<std::size_t>(s.ho), 0);
  need_rows_[static_cast<std::size_t>(s.node)].assign(static_cast<std::size_t>(s.ho), 0);
  comp_rows_[static_cast<std::size_t>(s.node)].assign(static_cast<std::size_t>(s.ho), 0);
  pad_.resize(std::max(pad_.size(), floats));
  // The gather's source vectors of one padded row (the same for every row and channel).
  s.cols.clear();
  const int sw = (s.w + 1) / 2;  // an upsampled source's width: w = 2·sw or 2·sw − 1
  for (int i0 = 0; i0 < s.pitch; i0 += detail::kLanes)
    for (int half = 0; half < s.stride; ++half) {
      Columns c;
      c.ix0 = (s2 ? 2 * i0 + half * detail::kLanes : i0) - s.pad_left;
      // Lane l of an upsampled row reads source column ⌊(ix0 + l)/2⌋ = sbase + ((shift + l) >> 1).
      c.sbase = detail::floor_div(c.ix0, 2);
      c.shift = c.ix0 - 2 * c.sbase;
      c.valid = lane_bits(-c.ix0, s.w - c.ix0);
      c.up_valid = lane_bits(-c.sbase, sw - c.sbase);
      s.cols.push_back(c);
    }
}

const float* InferencePlan::plane(const Source& src, const Tensor& x) const {
  const float* base = src.node < 0 ? x.data() : act_[static_cast<std::size_t>(src.node)].data();
  return base + static_cast<std::size_t>(src.channel) * static_cast<std::size_t>(src.plane);
}

// Gathers the padded rows [pr0, pr1) of the step's input (concatenation, upsampling and
// standardisation included) into xp — rows as pad_rows / pad_rows_s2 lay them out for Conv2d
// (xp's first row = padded row pr0) — or, for a flat step, into its flat layout (stride 1:
// xp's first row = padded row pr0 of every channel plane; stride 2: at their places in the
// phase planes).
void InferencePlan::gather_rows(const Step& s, const Tensor& x, int pr0, int pr1, float* xp) const {
#if defined(__AVX512F__)
  const int layout = s.stride == 1 ? 0 : s.flat ? 2 : 1;
  const long x_plane = s.flat ? s.x_plane : static_cast<long>(pr1 - pr0) * s.pitch * s.stride;
  for (int c = 0; c < s.cin; ++c) {
    const Source& src = s.src[static_cast<std::size_t>(c)];
    const Gather g{plane(src, x), src.pitch, s.h, s.w, s.pad_top, s.pad_left, s.rows, s.pitch, src.mean, src.inv, pr0, pr1};
    float* dst = xp + static_cast<std::size_t>(c) * static_cast<std::size_t>(x_plane);
    if (src.up) {
      src.standardise ? gather_channel<true, true>(g, s.cols, layout, dst) : gather_channel<true, false>(g, s.cols, layout, dst);
    } else {
      src.standardise ? gather_channel<false, true>(g, s.cols, layout, dst)
                      : gather_channel<false, false>(g, s.cols, layout, dst);
    }
  }
#else
  (void)s, (void)x, (void)pr0, (void)pr1, (void)xp;
#endif
}

// A flat step: the output rows [a, b) to compute (plan_rows: one run) — the padded rows they
// read gathered, then direct_flat over the run t ∈ [a·Wq, b·Wq) of the flat output (output t
// reads xp[c·x_plane + off[tap] + t] alone, so a run is computed with the whole plane's
// arithmetic). A rows step: each run of consecutive output rows to compute gathered and run
// through direct_tile, then the template rows that are read filled in. The same arithmetic
// per output element either way.
void InferencePlan::run_dense(const Step& s, const Tensor& x) {
#if defined(__AVX512F__)
  float* xp = pad_.data();
  float* y = act_[static_cast<std::size_t>(s.node)].data();
  const std::vector<char>& comp = comp_rows_[static_cast<std::size_t>(s.node)];
  if (s.flat) {
    const auto first = std::find(comp.begin(), comp.end(), 1);
    if (first == comp.end()) return;
    const int a = static_cast<int>(first - comp.begin());
    const int b = static_cast<int>(comp.rend() - std::find(comp.rbegin(), comp.rend(), 1));
    const long t0 = static_cast<long>(a) * s.pitch;
    if (s.stride == 1) {  // output row oy reads padded rows oy + ky, ky < k
      gather_rows(s, x, a, b - 1 + s.k, xp + t0);
    } else {  // output row oy reads padded rows 2·oy + ky, ky < 3 (phase rows oy and oy + 1)
      gather_rows(s, x, 2 * a, 2 * b + 1, xp);
    }
    detail::direct_flat(xp + t0, s.cin, s.x_plane, s.off.data(), s.k * s.k, s.weight.data(), s.cout, s.bias.data(), s.relu,
                        y + t0, static_cast<long>(s.ho) * s.pitch, static_cast<int>((b - a) * s.pitch));
    return;
  }
  for (int a = 0; a < s.ho;) {
    if (!comp[static_cast<std::size_t>(a)]) {
      ++a;
      continue;
    }
    int b = a + 1;
    while (b < s.ho && comp[static_cast<std::size_t>(b)]) ++b;
    // Output row j reads padded rows stride·j + ky, ky < k.
    const int pr0 = s.stride * a, pr1 = s.stride * (b - 1) + s.k;
    gather_rows(s, x, pr0, pr1, xp);
    detail::direct_tile(xp, s.cin, pr1 - pr0, s.pitch, s.k, s.weight.data(), s.cout, s.bias.data(), s.relu, y, s.ho,
                        s.wo, a, b - a, s.stride);
    a = b;
  }
  fill_template_rows(s);
#else
  (void)s, (void)x;
#endif
}

// The 1 × 1 head at the listed pixels: Network::forward_at's arithmetic per pixel (fused
// multiply-adds over the channels from 0, then + bias, then ReLU as std::max(r, 0)), evaluated
// row by row over the span of columns [head_lo_, head_hi_] that holds the row's listed pixels
// (plan_rows), 16 neighbouring pixels per vector: contiguous loads of the sources' rows (an
// upsampled source through a lane permutation) instead of per-pixel gathers. The other
// pixels of a span are computed too (unspecified output); rows without pixels are skipped.
void InferencePlan::run_sparse(const Step& s, const Tensor& x, std::span<const int> pixels) {
  const int W = out_shape_.w, P = out_shape_.h * out_shape_.w;
  for (const int p : pixels)
    if (p < 0 || p >= P) throw InvalidArgument("InferencePlan::run: pixel " + std::to_string(p) + " outside the output");
#if defined(__AVX512F__)
  constexpr int kB = detail::kLanes;
  const int cin = s.cin, sw = (W + 1) / 2;
  float* v = block_.data();
  const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  for (int c = 0; c < cin; ++c) bases_[static_cast<std::size_t>(c)] = plane(s.src[static_cast<std::size_t>(c)], x);
  for (int Y = 0; Y < out_shape_.h; ++Y) {
    const int lo = head_lo_[static_cast<std::size_t>(Y)], hi = head_hi_[static_cast<std::size_t>(Y)];
    for (int x0 = lo; x0 <= hi; x0 += kB) {
      const auto m = static_cast<__mmask16>((1u << std::min(kB, hi - x0 + 1)) - 1u);
      const int sbase = x0 / 2, shift = x0 - 2 * sbase;  // lane l reads source column sbase + ((shift + l) >> 1)
      const auto up_m = static_cast<__mmask16>((1u << std::clamp(sw - sbase, 0, kB)) - 1u);
      const __m512i idx = _mm512_srai_epi32(_mm512_add_epi32(iota, _mm512_set1_epi32(shift)), 1);
      for (int c = 0; c < cin; ++c) {
        const Source& src = s.src[static_cast<std::size_t>(c)];
        const float* base = bases_[static_cast<std::size_t>(c)];
        __m512 value;
        if (src.up) {
          const __m512 row = _mm512_maskz_loadu_ps(up_m, base + static_cast<std::size_t>(Y / 2) * sw + sbase);
          value = _mm512_maskz_mov_ps(m, _mm512_permutexvar_ps(idx, row));
        } else {
          value = _mm512_maskz_loadu_ps(m, base + static_cast<std::size_t>(Y) * W + x0);
        }
        if (src.standardise) value = _mm512_mul_ps(_mm512_sub_ps(value, _mm512_set1_ps(src.mean)), _mm512_set1_ps(src.inv));
        _mm512_storeu_ps(v + static_cast<std::size_t>(c) * kB, value);
      }
      for (int o = 0; o < s.cout; ++o) {
        const float* wo = s.weight.data() + static_cast<std::size_t>(o) * cin;
        __m512 acc = _mm512_setzero_ps();
        for (int c = 0; c < cin; ++c)
          acc = _mm512_fmadd_ps(_mm512_set1_ps(wo[c]), _mm512_loadu_ps(v + static_cast<std::size_t>(c) * kB), acc);
        __m512 r = _mm512_add_ps(acc, _mm512_set1_ps(s.bias[static_cast<std::size_t>(o)]));
        if (s.relu) r = _mm512_max_ps(_mm512_setzero_ps(), r);  // r when NaN or −0, as std::max(r, 0)
        _mm512_mask_storeu_ps(out_.data() + static_cast<std::size_t>(o) * P + static_cast<std::size_t>(Y) * W + x0, m, r);
      }
    }
  }
#else
  (void)s, (void)x, (void)W;
#endif
}

const Tensor& InferencePlan::run(const Tensor& features, std::span<const int> pixels, std::vector<double>* step_ms) {
  return run_plan(features, pixels, nullptr, step_ms);
}

const Tensor& InferencePlan::run(const Tensor& features, std::span<const int> pixels, InputRows rows,
                                 std::vector<double>* step_ms) {
  return run_plan(features, pixels, &rows, step_ms);
}

const Tensor& InferencePlan::run_plan(const Tensor& features, std::span<const int> pixels, const InputRows* rows,
                                      std::vector<double>* step_ms) {
  require_shape(features.shape(), in_, "InferencePlan::run input");
  if (step_ms) step_ms->assign(step_count(), 0.0);
  if (!fused()) {
    const double t0 = step_ms ? detail::thread_cpu_ms() : 0.0;
    scratch_ = features;
    stats_.apply(scratch_);
    net_->forward_at(scratch_, pixels, out_);
    if (step_ms) (*step_ms)[0] = detail::thread_cpu_ms() - t0;
    return out_;
  }
  plan_rows(features, pixels, false, rows);
  for (std::size_t i = 0; i < steps_.size(); ++i) {
    const double t0 = step_ms ? detail::thread_cpu_ms() : 0.0;
    const Step& s = steps_[i];
    if (s.sparse) {
      run_sparse(s, features, pixels);
    } else {
      run_dense(s, features);
    }
    if (step_ms) (*step_ms)[i] = detail::thread_cpu_ms() - t0;
  }
  return steps_.back().sparse ? out_ : act_.back();
}

std::string InferencePlan::step_name(std::size_t i) const {
  if (!fused()) return "network";
  return net_->node_name(static_cast<std::size_t>(steps_.at(i).node));
}

}  // namespace dc
