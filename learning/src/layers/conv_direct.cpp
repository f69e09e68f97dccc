// The direct convolution kernels (see conv_direct.hpp).
#include "layers/conv_direct.hpp"

#include <algorithm>
#include <cstring>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace dc::detail {

bool direct_available(int s, int wo) {
#if defined(__AVX512F__)
  return s == 1 && wo <= kLanes * kMaxVec;
#else
  (void)s;
  (void)wo;
  return false;
#endif
}
// Output channels per register block: OB·VB ≤ 24 accumulators.
// (A layer with ≤ 2 output channels, like the U-Net's head, uses blocks of 2.)
int block_channels(int wo, int cout) {
  if (cout <= 2) return 2;
  return vec_count(wo) >= 4 ? 4 : 8;
}

// wpk[(b·C + c)·k² + tap][j] = w(o = b·OB + j, c, tap), zero for o ≥ Cout.
// w(o, c, tap) = src[o·so + (c·k² + tap)·sc].
void pack_weights(const float* src, long so, long sc, int cout, int cin, int kk, int ob, std::vector<float>& wpk) {
  const int nb = (cout + ob - 1) / ob;
  wpk.assign(static_cast<std::size_t>(nb) * cin * kk * ob, 0.0f);
  for (int o = 0; o < cout; ++o)
    for (int ct = 0; ct < cin * kk; ++ct)
      wpk[(static_cast<std::size_t>(o / ob) * cin * kk + ct) * ob + o % ob] = src[o * so + ct * sc];
}

// Copies input rows [r0 − p, r0 − p + R) of x [C][H][W] into xp [C][R][Wp] at column p,
// zero elsewhere. mask (optional, same layout as x): element kept where mask > 0.
void pad_rows(const float* x, const float* mask, int C, int H, int W, int p, int r0, int R, int Wp, float* xp) {
  for (int c = 0; c < C; ++c) {
    for (int r = 0; r < R; ++r) {
      float* dst = xp + (static_cast<std::size_t>(c) * R + r) * Wp;
      const int iy = r0 - p + r;
      if (iy < 0 || iy >= H) {
        std::memset(dst, 0, sizeof(float) * Wp);
        continue;
      }
      std::memset(dst, 0, sizeof(float) * p);
      const std::size_t off = (static_cast<std::size_t>(c) * H + iy) * W;
      if (mask == nullptr) {
        std::memcpy(dst + p, x + off, sizeof(float) * W);
      } else {
        for (int ix = 0; ix < W; ++ix) dst[p + ix] = mask[off + ix] > 0.0f ? x[off + ix] : 0.0f;
      }
      std::memset(dst + p + W, 0, sizeof(float) * (Wp - p - W));
    }
  }
}

#if defined(__AVX512F__)
// KS: the kernel size if known at compile time (fully unrolled taps), 0 = use k.
// S: stride 1 or 2. For stride 2 the padded rows are split into column phases,
// xp [C][R][S][Wp] with phase φ index i = padded column S·i + φ, so that tap kx of output
// column ox reads phase kx % S at index ox + kx / S: contiguous again. Output row j reads
// padded row S·j + ky.
template <int VB, int OB, int KS, int S>
void direct_rows(const float* xp, int C, int R, int Wp, int kdyn, const float* wpk, int cout, const float* bias,
                 bool relu, float* y, int ho, int wo, int oy0, int nrows) {
  const int k = KS > 0 ? KS : kdyn;
  const int nb = (cout + OB - 1) / OB;
  const int kk = k * k;
  for (int j = 0; j < nrows; ++j) {
    for (int b = 0; b < nb; ++b) {
      __m512 acc[OB][VB];
      for (int o = 0; o < OB; ++o)
        for (int v = 0; v < VB; ++v) acc[o][v] = _mm512_setzero_ps();
      const float* wb = wpk + static_cast<std::size_t>(b) * C * kk * OB;
      for (int c = 0; c < C; ++c) {
        for (int ky = 0; ky < k; ++ky) {
          const float* xr = xp + (static_cast<std::size_t>(c) * R + j * S + ky) * S * Wp;
          const float* wr = wb + static_cast<std::size_t>(c * kk + ky * k) * OB;
          for (int kx = 0; kx < k; ++kx, wr += OB) {
            __m512 xv[VB];
            const float* xk = xr + (kx % S) * Wp + kx / S;
            for (int v = 0; v < VB; ++v) {
              xv[v] = _mm512_loadu_ps(xk + v * kLanes);
              // Keep the loaded row in a register: without this GCC folds the load into
              // each of the OB FMAs (OB unaligned loads instead of one; load-bound).
              __asm__("" : "+v"(xv[v]));
            }
            for (int o = 0; o < OB; ++o) {
              const __m512 wv = _mm512_set1_ps(wr[o]);
              for (int v = 0; v < VB; ++v) acc[o][v] = _mm512_fmadd_ps(wv, xv[v], acc[o][v]);
            }
          }
        }
      }
      const int on = std::min(OB, cout - b * OB);
      for (int o = 0; o < on; ++o) {
        const int oc = b * OB + o;
        float* yr = y + (static_cast<std::size_t>(oc) * ho + oy0 + j) * wo;
        const __m512 bv = _mm512_set1_ps(bias == nullptr ? 0.0f : bias[oc]);
        for (int v = 0; v < VB; ++v) {
          __m512 r = bias == nullptr ? acc[o][v] : _mm512_add_ps(acc[o][v], bv);
          if (relu) r = _mm512_max_ps(r, _mm512_setzero_ps());
          const int n = std::min(kLanes, wo - v * kLanes);
          _mm512_mask_storeu_ps(yr + v * kLanes, static_cast<__mmask16>((1u << n) - 1u), r);
        }
      }
    }
  }
}
#endif

// Output rows [oy0, oy0 + nrows) of y [cout][ho][wo] from the padded rows in xp.
void direct_tile(const float* xp, int C, int R, int Wp, int k, const float* wpk, int cout, const float* bias, bool relu,
                 float* y, int ho, int wo, int oy0, int nrows, int stride) {
#if defined(__AVX512F__)
#define DC_ROWS(VB, OB)                                                                          \
  if (stride == 2)                                                                              \
    direct_rows<VB, OB, 3, 2>(xp, C, R, Wp, k, wpk, cout, bias, relu, y, ho, wo, oy0, nrows);   \
  else if (k == 3)                                                                              \
    direct_rows<VB, OB, 3, 1>(xp, C, R, Wp, k, wpk, cout, bias, relu, y, ho, wo, oy0, nrows);   \
  else                                                                                          \
    direct_rows<VB, OB, 0, 1>(xp, C, R, Wp, k, wpk, cout, bias, relu, y, ho, wo, oy0, nrows);
  if (cout <= 2) {
    switch (vec_count(wo)) {
      case 1: DC_ROWS(1, 2) break;
      case 2: DC_ROWS(2, 2) break;
      case 3: DC_ROWS(3, 2) break;
      default: DC_ROWS(4, 2) break;
    }
    return;
  }
  switch (vec_count(wo)) {
    case 1: DC_ROWS(1, 8) break;
    case 2: DC_ROWS(2, 8) break;
    case 3: DC_ROWS(3, 8) break;
    default: DC_ROWS(4, 4) break;
  }
#undef DC_ROWS
#else
  (void)xp, (void)C, (void)R, (void)Wp, (void)k, (void)wpk, (void)cout, (void)bias, (void)relu;
  (void)y, (void)ho, (void)wo, (void)oy0, (void)nrows, (void)stride;
#endif
}

// Stride-2 padded rows for direct_rows<…, 2>: xp [C][R][2][Wp], padded row r = input row
// r0 + r, phase φ index i = input column 2i + φ − pl; zero outside the image.
void pad_rows_s2(const float* x, int C, int H, int W, int pl, int r0, int R, int Wp, float* xp) {
  for (int c = 0; c < C; ++c) {
    for (int r = 0; r < R; ++r) {
      float* dst = xp + (static_cast<std::size_t>(c) * R + r) * 2 * Wp;
      const int iy = r0 + r;
      if (iy < 0 || iy >= H) {
        std::memset(dst, 0, sizeof(float) * 2 * Wp);
        continue;
      }
      const float* src = x + (static_cast<std::size_t>(c) * H + iy) * W;
      for (int ph = 0; ph < 2; ++ph, dst += Wp)
        for (int i = 0; i < Wp; ++i) {
          const int ix = 2 * i + ph - pl;
          dst[i] = ix >= 0 && ix < W ? src[ix] : 0.0f;
        }
    }
  }
}

#if defined(__AVX512F__)
// One chunk of VB vectors of the flat output, all output channel blocks of OB.
template <int VB, int OB>
void direct_flat_chunk(const float* xp, int C, long x_plane, const int* off, int kk, const float* wpk, int cout,
                       const float* bias, bool relu, float* y, long y_plane, int t0, int n) {
  const int nb = (cout + OB - 1) / OB;
  for (int b = 0; b < nb; ++b) {
    __m512 acc[OB][VB];
    for (int o = 0; o < OB; ++o)
      for (int v = 0; v < VB; ++v) acc[o][v] = _mm512_setzero_ps();
    const float* wr = wpk + static_cast<std::size_t>(b) * C * kk * OB;
    for (int c = 0; c < C; ++c) {
      const float* xc = xp + static_cast<std::size_t>(c) * x_plane + t0;
      for (int tap = 0; tap < kk; ++tap, wr += OB) {
        __m512 xv[VB];
        for (int v = 0; v < VB; ++v) {
          xv[v] = _mm512_loadu_ps(xc + off[tap] + v * kLanes);
          __asm__("" : "+v"(xv[v]));  // one load per vector (see direct_rows)
        }
        for (int o = 0; o < OB; ++o) {
          const __m512 wv = _mm512_set1_ps(wr[o]);
          for (int v = 0; v < VB; ++v) acc[o][v] = _mm512_fmadd_ps(wv, xv[v], acc[o][v]);
        }
      }
    }
    const int on = std::min(OB, cout - b * OB);
    for (int o = 0; o < on; ++o) {
      const int oc = b * OB + o;
      float* yr = y + static_cast<std::size_t>(oc) * y_plane + t0;
      const __m512 bv = _mm512_set1_ps(bias == nullptr ? 0.0f : bias[oc]);
      for (int v = 0; v < VB; ++v) {
        __m512 r = bias == nullptr ? acc[o][v] : _mm512_add_ps(acc[o][v], bv);
        if (relu) r = _mm512_max_ps(r, _mm512_setzero_ps());
        const int m = std::clamp(n - t0 - v * kLanes, 0, kLanes);
        _mm512_mask_storeu_ps(yr + v * kLanes, static_cast<__mmask16>((1u << m) - 1u), r);
      }
    }
  }
}
#endif

void direct_flat(const float* xp, int C, long x_plane, const int* off, int kk, const float* wpk, int cout,
                 const float* bias, bool relu, float* y, long y_plane, int n) {
#if defined(__AVX512F__)
  // Chunks of up to 3 vectors: 8·3 accumulators + 3 loaded vectors fit the 32 registers.
  for (int t0 = 0; t0 < n; t0 += 3 * kLanes) {
    const int vb = std::min(3, vec_count(n - t0));
    const bool two = cout <= 2;
#define DC_FLAT(VB)                                                                                      \
  if (two)                                                                                               \
    direct_flat_chunk<VB, 2>(xp, C, x_plane, off, kk, wpk, cout, bias, relu, y, y_plane, t0, n);          \
  else                                                                                                   \
    direct_flat_chunk<VB, 8>(xp, C, x_plane, off, kk, wpk, cout, bias, relu, y, y_plane, t0, n);
    switch (vb) {
      case 1: DC_FLAT(1) break;
      case 2: DC_FLAT(2) break;
      default: DC_FLAT(3) break;
    }
#undef DC_FLAT
  }
#else
  (void)xp, (void)C, (void)x_plane, (void)off, (void)kk, (void)wpk, (void)cout, (void)bias, (void)relu;
  (void)y, (void)y_plane, (void)n;
#endif
}

}  // namespace dc::detail
