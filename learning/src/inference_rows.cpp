// InferencePlan's row bookkeeping: which output rows of each step run() computes (demand,
// propagated backwards from the head's pixels) and which it copies from the step's template
// row (rows that read only empty-box rows). Both are exact: every computed element has the
// arithmetic of the full evaluation and every element that is read holds its bits. Flat steps
// compute one run of rows and copy no template rows. The input's empty rows are scanned (all
// channels +0 as bit patterns) or handed over by the caller; rows inside a handed range are
// taken as not empty. Derivation: docs/learning.md "The fused inference plan".
#include <algorithm>
#include <cstdint>
#include <cstring>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "dc/learning/inference_plan.hpp"

namespace dc {

namespace {

/// Whether the n floats at v are all +0 (bit pattern 0).
bool all_plus_zero(const float* v, int n) {
#if defined(__AVX512F__)
  __m512i bits = _mm512_setzero_si512();
  for (int i = 0; i < n; i += 16) {
    const auto m = static_cast<__mmask16>((1u << std::min(16, n - i)) - 1u);
    bits = _mm512_or_si512(bits, _mm512_maskz_loadu_epi32(m, v + i));
  }
  return _mm512_test_epi32_mask(bits, bits) == 0;
#else
  std::uint32_t bits = 0;
  for (int i = 0; i < n; ++i) {
    std::uint32_t b;
    std::memcpy(&b, v + i, sizeof b);
    bits |= b;
  }
  return bits == 0;
#endif
}

/// The first and last index of a nonzero byte among row[0, n): lo > hi (n, −1) when none.
void marked_span(const char* row, int n, int& lo, int& hi) {
  lo = n;
  hi = -1;
#if defined(__AVX512BW__)
  for (int i = 0; i < n; i += 64) {
    const __mmask64 in = n - i >= 64 ? ~0ULL : (1ULL << (n - i)) - 1ULL;
    const __mmask64 set = _mm512_test_epi8_mask(_mm512_maskz_loadu_epi8(in, row + i), _mm512_set1_epi8(-1));
    if (set == 0) continue;
    if (lo == n) lo = i + static_cast<int>(__builtin_ctzll(set));
    hi = i + 63 - static_cast<int>(__builtin_clzll(set));
  }
#else
  for (int i = 0; i < n; ++i)
    if (row[i]) {
      lo = std::min(lo, i);
      hi = i;
    }
#endif
}

}  // namespace

bool InferencePlan::reads_templates(const Step& s, int oy) const {
  for (int ky = 0; ky < s.k; ++ky) {
    const int iy = s.stride * oy + ky - s.pad_top;
    if (iy < 0 || iy >= s.h) return false;  // padding: not what the template row read
    for (const auto& [node, up] : s.inputs) {
      const auto row = static_cast<std::size_t>(up ? iy / 2 : iy);
      if (!(node < 0 ? empty_in_[row] : tmpl_rows_[static_cast<std::size_t>(node)][row])) return false;
    }
  }
  return true;
}

void InferencePlan::plan_rows(const Tensor& x, std::span<const int> pixels, bool all, const InputRows* rows) {
  const int C = in_.c, H = in_.h, W = in_.w;
  const bool templates = std::any_of(steps_.begin(), steps_.end(), [](const Step& s) { return s.has_template; });
  empty_in_.assign(static_cast<std::size_t>(H), 0);
  if (templates && rows != nullptr) {  // the caller's word: +0 outside [lo, hi]
    for (int y = 0; y < H; ++y) empty_in_[static_cast<std::size_t>(y)] = y < rows->lo || y > rows->hi;
  }
  for (int y = 0; templates && rows == nullptr && y < H; ++y) {
    bool empty = true;  // the OR of the row's raw bit patterns over all channels is 0: all +0
    for (int c = 0; c < C && empty; ++c) empty = all_plus_zero(x.data() + (static_cast<std::size_t>(c) * H + y) * W, W);
    empty_in_[static_cast<std::size_t>(y)] = empty;
  }
  for (const Step& s : steps_) {
    if (s.sparse) continue;
    std::vector<char>& t = tmpl_rows_[static_cast<std::size_t>(s.node)];
    for (int oy = 0; oy < s.ho; ++oy) t[static_cast<std::size_t>(oy)] = s.has_template && reads_templates(s, oy);
  }
  for (std::vector<char>& n : need_rows_) std::fill(n.begin(), n.end(), 0);
  const Step& last = steps_.back();
  if (last.sparse) {
    const int P = out_shape_.h * out_shape_.w;
    // A byte per output pixel (independent stores, no chain of min/max through memory), then
    // each row's first and last marked column.
    mark_.assign(static_cast<std::size_t>(P), 0);
    for (const int p : pixels)
      if (p >= 0 && p < P) mark_[static_cast<std::size_t>(p)] = 1;  // others: refused by run_sparse
    head_lo_.resize(static_cast<std::size_t>(out_shape_.h));
    head_hi_.resize(static_cast<std::size_t>(out_shape_.h));
    int* lo = head_lo_.data();
    int* hi = head_hi_.data();
    for (int Y = 0; Y < out_shape_.h; ++Y) marked_span(mark_.data() + static_cast<std::size_t>(Y) * out_shape_.w, out_shape_.w, lo[Y], hi[Y]);
    for (int Y = 0; Y < out_shape_.h; ++Y) {
      if (hi[Y] < 0) continue;
      for (const auto& [node, up] : last.inputs)
        if (node >= 0) need_rows_[static_cast<std::size_t>(node)][static_cast<std::size_t>(up ? Y / 2 : Y)] = 1;
    }
  } else {
    std::vector<char>& n = need_rows_[static_cast<std::size_t>(last.node)];
    std::fill(n.begin(), n.end(), 1);
  }
  for (auto it = steps_.rbegin(); it != steps_.rend(); ++it) {
    const Step& s = *it;
    if (s.sparse) continue;
    const auto node = static_cast<std::size_t>(s.node);
    // A flat step computes one run of rows: from its first to its last needed row (no
    // template copies: its rows share vectors).
    int flat_lo = s.ho, flat_hi = -1;
    if (s.flat)
      for (int oy = 0; oy < s.ho; ++oy)
        if (all || need_rows_[node][static_cast<std::size_t>(oy)]) {
          flat_lo = std::min(flat_lo, oy);
          flat_hi = oy;
        }
    for (int oy = 0; oy < s.ho; ++oy) {
      const auto r = static_cast<std::size_t>(oy);
      comp_rows_[node][r] = s.flat ? oy >= flat_lo && oy <= flat_hi
                                   : all || (need_rows_[node][r] && !tmpl_rows_[node][r]);
      if (!comp_rows_[node][r]) continue;
      for (int ky = 0; ky < s.k; ++ky) {
        const int iy = s.stride * oy + ky - s.pad_top;
        if (iy < 0 || iy >= s.h) continue;
        for (const auto& [from, up] : s.inputs)
          if (from >= 0) need_rows_[static_cast<std::size_t>(from)][static_cast<std::size_t>(up ? iy / 2 : iy)] = 1;
      }
    }
  }
}

void InferencePlan::fill_template_rows(const Step& s) {
  if (!s.has_template || s.flat) return;
  const auto node = static_cast<std::size_t>(s.node);
  float* y = act_[node].data();
  for (int oy = 0; oy < s.ho; ++oy) {
    const auto r = static_cast<std::size_t>(oy);
    if (!need_rows_[node][r] || !tmpl_rows_[node][r] || comp_rows_[node][r]) continue;
    for (int oc = 0; oc < s.cout; ++oc)
      std::memcpy(y + (static_cast<std::size_t>(oc) * s.ho + r) * s.wo, s.tmpl.data() + static_cast<std::size_t>(oc) * s.wo,
                  sizeof(float) * static_cast<std::size_t>(s.wo));
  }
}

// Every dense step assumed to have a template, the whole plan run on an all-zero input (every
// row computed); a step's template is then its output in any row flagged as a template row —
// the same bits in all of them (checked: otherwise templates stay off altogether). A step
// whose rows are never flagged (its output sees padding everywhere) gets none.
void InferencePlan::calibrate_templates() {
  for (Step& s : steps_) s.has_template = !s.sparse;
  const Tensor zero(in_);
  plan_rows(zero, {}, true, nullptr);
  for (const Step& s : steps_)
    if (!s.sparse) run_dense(s, zero);
  bool consistent = true;
  for (Step& s : steps_) {
    if (s.sparse) continue;
    const auto node = static_cast<std::size_t>(s.node);
    const std::vector<char>& t = tmpl_rows_[node];
    const long y_plane = s.flat ? static_cast<long>(s.ho) * s.pitch : static_cast<long>(s.ho) * s.wo;
    const int row_pitch = s.flat ? s.pitch : s.wo;
    const float* y = act_[node].data();
    s.tmpl.clear();
    s.has_template = false;
    for (int oy = 0; oy < s.ho; ++oy) {
      if (!t[static_cast<std::size_t>(oy)]) continue;
      std::vector<float> row;
      for (int oc = 0; oc < s.cout; ++oc) {
        const float* at = y + oc * y_plane + static_cast<long>(oy) * row_pitch;
        row.insert(row.end(), at, at + s.wo);
      }
      if (!s.has_template) {
        s.tmpl = std::move(row);
        s.has_template = true;
      } else if (std::memcmp(row.data(), s.tmpl.data(), sizeof(float) * row.size()) != 0) {
        consistent = false;
      }
    }
  }
  if (!consistent)
    for (Step& s : steps_) s.has_template = false;
}

}  // namespace dc
