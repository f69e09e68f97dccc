#pragma once
// Private: the direct convolution kernels shared by Conv2d and the fused inference plan.
// AVX-512 builds only; elsewhere direct_available() is false and the other entry points must
// not be called. For an output row of at most 4 vectors of 16 floats (Wo ≤ 64): the input rows
// a tile needs are copied into a zero-padded buffer xp [C][R][Wp] (padded row r = input row
// oy0 + r − p, column p + ix = input column ix; Wp leaves room for the last vector of every
// shifted row), weights packed as wpk [Cout/OB][C][k][k][OB], each output row × OB channels
// accumulated in OB·VB zmm registers. The summation order of an output element is (c, ky, kx),
// then + bias, then the optional ReLU, whatever the tile, thread or caller: the plan and
// Conv2d::forward give the same bits.
#include <vector>

namespace dc::detail {

constexpr int kLanes = 16;  ///< floats per AVX-512 vector
constexpr int kMaxVec = 4;  ///< Wo ≤ 64

/// True when this build has the direct kernels and they serve stride s at output width wo:
/// stride 1 (any odd k) only; callers use the stride-2 (3 × 3) kernel where
/// direct_available(1, wo) holds.
bool direct_available(int s, int wo);
/// Vectors of 16 lanes per output row.
inline int vec_count(int wo) { return (wo + kLanes - 1) / kLanes; }
/// Output channels per register block: OB·VB ≤ 24 accumulators (2 for ≤ 2 channels).
int block_channels(int wo, int cout);
/// Row pitch of a stride-1 padded buffer: whole vectors plus the k − 1 halo.
inline int padded_width(int wo, int k) { return vec_count(wo) * kLanes + k - 1; }
/// Row pitch of each column phase of a stride-2 (3 × 3) padded buffer.
inline int padded_width_s2(int wo) { return vec_count(wo) * kLanes + 1; }

/// wpk[(b·C + c)·k² + tap][j] = w(o = b·OB + j, c, tap), zero for o ≥ Cout, where
/// w(o, c, tap) = src[o·so + (c·k² + tap)·sc]. `wpk` is resized (reused when large enough).
void pack_weights(const float* src, long so, long sc, int cout, int cin, int kk, int ob, std::vector<float>& wpk);

/// Copies input rows [r0 − p, r0 − p + R) of x [C][H][W] into xp [C][R][Wp] at column p,
/// zero elsewhere. mask (optional, same layout as x): element kept where mask > 0.
void pad_rows(const float* x, const float* mask, int C, int H, int W, int p, int r0, int R, int Wp, float* xp);

/// Stride-2 padded rows for the stride-2 kernel: xp [C][R][2][Wp], padded row r = input row
/// r0 + r, phase φ index i = input column 2i + φ − pl; zero outside the image.
void pad_rows_s2(const float* x, int C, int H, int W, int pl, int r0, int R, int Wp, float* xp);

/// Output rows [oy0, oy0 + nrows) of y [cout][ho][wo] from the padded rows in xp (stride 1:
/// [C][R][Wp]; stride 2, k = 3: [C][R][2][Wp]); weights packed by pack_weights with
/// block_channels(wo, cout); bias may be null (no bias added).
void direct_tile(const float* xp, int C, int R, int Wp, int k, const float* wpk, int cout, const float* bias, bool relu,
                 float* y, int ho, int wo, int oy0, int nrows, int stride = 1);

/// The flat variant for small images, where an output row fills few of a vector's 16 lanes
/// (a 4 × 4 output would use 4): the output plane is one flat run t = oy·Wq + ox of
/// n = Ho·Wq elements (row pitch Wq = Wo + halo; the columns ox ≥ Wo are don't-care values,
/// computed from whatever the buffer holds there, and later never read), and input channel
/// c's tap `tap` (= ky·k + kx) of output t is xp[c·x_plane + off[tap] + t]. Stride 1 lays
/// the padded input out as rows of pitch Wq (off = ky·Wq + kx); stride 2 as four phase planes
/// of padded rows/columns (2i + ρ, 2j + φ) (off = phase(ky%2, kx%2) + (ky/2)·Wq + kx/2).
/// Lanes are read up to 16·⌈n/16⌉ + max(off) past c·x_plane: the buffer must extend that
/// far. y[oc·y_plane + t] for t < n; the (c, tap) summation order, bias and ReLU are
/// direct_tile's, so every output element has direct_tile's bits. Weights packed with
/// flat_block_channels(cout).
void direct_flat(const float* xp, int C, long x_plane, const int* off, int kk, const float* wpk, int cout,
                 const float* bias, bool relu, float* y, long y_plane, int n);
/// Output channels per register block of direct_flat.
inline int flat_block_channels(int cout) { return cout <= 2 ? 2 : 8; }

}  // namespace dc::detail
