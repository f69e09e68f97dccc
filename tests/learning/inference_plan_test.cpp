// InferencePlan: the fused, forward-only evaluation gives the unfused path's values
// (standardise a copy, Network::forward_at) bit for bit at the listed pixels, for U-Nets of
// the shipped architecture's shape on odd and even grids, with and without ReLU in the
// head; it agrees with the dense forward; a fused plan is a snapshot of the weights; unsupported
// graphs run the unfused path; bad inputs are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"
#include "dc/learning/arch.hpp"
#include "dc/learning/channel_stats.hpp"
#include "dc/learning/inference_plan.hpp"
#include "dc/learning/initializer.hpp"
#include "dc/learning/network.hpp"
#include "grad_check.hpp"
#include "small_archs.hpp"

namespace dc {
namespace {

using test::fill_gaussian;

/// Random weights and biases (biases non-zero: the bias add is part of the compared path).
void randomise(Network& net, std::uint64_t seed) {
  Rng rng(seed);
  net.initialize(HeNormal(), rng);
  for (ParamRef& p : net.parameters())
    if (!p.decay) fill_gaussian(*p.value, rng, 0.1);
}

/// Input statistics that are not the identity (the standardisation is fused in the plan).
ChannelStats some_stats(int channels) {
  ChannelStats s;
  for (int c = 0; c < channels; ++c) {
    s.mean.push_back(0.3f * static_cast<float>(c) - 0.4f);
    s.std.push_back(0.5f + 0.7f * static_cast<float>(c));
  }
  return s;
}

/// The unfused path: what Model::network_output_at computes.
Tensor unfused(Network& net, const ChannelStats& stats, const Tensor& features, const std::vector<int>& pixels) {
  Tensor x = features, out;
  stats.apply(x);
  net.forward_at(x, pixels, out);
  return out;
}

std::vector<int> every_third_pixel(int P) {
  std::vector<int> pixels;
  for (int p = 0; p < P; p += 3) pixels.push_back(p);
  pixels.push_back(P - 1);  // the odd last row and column of the nearest upsamplings
  return pixels;
}

TEST(InferencePlan, FusedEqualsTheUnfusedPathBitForBit) {
  for (const auto& [h, w] : {std::pair{13, 11}, std::pair{16, 16}, std::pair{61, 61}, std::pair{9, 40}}) {
    for (const bool relu : {false, true}) {
      Network net(test::fast_head_arch(relu), Shape{1, 3, h, w});
      randomise(net, static_cast<std::uint64_t>(h * 100 + w + relu));
      const ChannelStats stats = some_stats(3);
      Rng rng(3);
      Tensor f(1, 3, h, w);
      fill_gaussian(f, rng, 2.0);
      const std::vector<int> pixels = every_third_pixel(h * w);
      InferencePlan plan(net, stats);
#if defined(__AVX512F__)
      EXPECT_TRUE(plan.fused()) << h << "x" << w;
#endif
      const Tensor want = unfused(net, stats, f, pixels);
      std::vector<double> ms;
      const Tensor& got = plan.run(f, pixels, &ms);
      ASSERT_EQ(got.shape(), want.shape());
      EXPECT_EQ(ms.size(), plan.step_count());
      for (int c = 0; c < 2; ++c)
        for (const int p : pixels) {
          const std::size_t i = static_cast<std::size_t>(c * h * w + p);
          EXPECT_EQ(got[i], want[i]) << h << "x" << w << " relu " << relu << " channel " << c << " pixel " << p;
        }
      // And the dense forward of the standardised input (to rounding: the portable GEMM path).
      Tensor x = f;
      stats.apply(x);
      const Tensor dense = net.forward(x, false);
      for (int c = 0; c < 2; ++c)
        for (const int p : pixels) {
          const std::size_t i = static_cast<std::size_t>(c * h * w + p);
          EXPECT_NEAR(got[i], dense[i], 1e-5f * (1.0f + std::abs(dense[i])));
        }
    }
  }
}

// The shipped architecture's shape in full: a 4 × 4 bottleneck and 3×3 stride-1 decoder
// convs on small outputs (the flat kernel layout), a 1×1 merge and the per-node head.
ArchSpec deep_fast_arch() {
  return ArchSpec::parse(R"(
name = "deep-fast"
[[layer]]
name = "e1"
type = "conv"
out = 8
stride = 2
relu = true
[[layer]]
name = "e2"
type = "conv"
out = 16
stride = 2
relu = true
[[layer]]
name = "e3"
type = "conv"
out = 16
stride = 2
relu = true
[[layer]]
name = "u2"
type = "upsample"
match = "e2"
[[layer]]
name = "d2"
type = "conv"
input = ["u2", "e2"]
out = 8
relu = true
[[layer]]
name = "u1"
type = "upsample"
match = "e1"
[[layer]]
name = "d1"
type = "conv"
input = ["u1", "e1"]
out = 8
kernel = 1
relu = true
[[layer]]
name = "u0"
type = "upsample"
match = "input"
[[layer]]
name = "out"
type = "conv"
input = ["u0", "input"]
out = 2
kernel = 1
)");
}

TEST(InferencePlan, FusedEqualsTheUnfusedPathOnTheShippedShape) {
  for (const auto& [h, w] : {std::pair{29, 29}, std::pair{30, 27}}) {
    Network net(deep_fast_arch(), Shape{1, 4, h, w});
    randomise(net, static_cast<std::uint64_t>(h + w));
    const ChannelStats stats = some_stats(4);
    Rng rng(9);
    Tensor f(1, 4, h, w);
    fill_gaussian(f, rng, 2.0);
    const std::vector<int> pixels = every_third_pixel(h * w);
    InferencePlan plan(net, stats);
    const Tensor want = unfused(net, stats, f, pixels);
    const Tensor& got = plan.run(f, pixels);
    for (int c = 0; c < 2; ++c)
      for (const int p : pixels) {
        const std::size_t i = static_cast<std::size_t>(c * h * w + p);
        EXPECT_EQ(got[i], want[i]) << h << "x" << w << " channel " << c << " pixel " << p;
      }
  }
}

/// Float bit patterns: the skipped rows must give the same bits, −0 and NaN included.
std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }

/// 4 channels of h × w Gaussian features (σ 2) in rows [lo, hi), +0 everywhere else: an image
/// whose empty rows the plan can skip or copy from its template rows.
Tensor banded_features(Rng& rng, int h, int w, int lo, int hi) {
  Tensor f(1, 4, h, w);
  fill_gaussian(f, rng, 2.0);
  for (int c = 0; c < 4; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (y < lo || y >= hi) f.at(0, c, y, x) = 0.0f;
  return f;
}

// A mostly empty box (the seed pile fills the lower part): raw features +0 outside a band of
// rows, one empty-looking row holding a −0 (not an empty row: −0 standardises to other bits).
// run() then skips rows the pixels do not depend on and copies template rows; over calls with
// other pixels and other bands (stale rows in the buffers) it stays equal to the unfused path.
TEST(InferencePlan, RowsSkippedOnAPartlyEmptyImageGiveTheSameBits) {
  for (const auto& [h, w] : {std::pair{61, 61}, std::pair{45, 38}}) {
    for (const bool deep : {false, true}) {
      Network net(deep ? deep_fast_arch() : test::fast_head_arch(true), Shape{1, 4, h, w});
      randomise(net, static_cast<std::uint64_t>(h + w + deep));
      const ChannelStats stats = some_stats(4);
      InferencePlan plan(net, stats);
      Rng rng(11);
      for (const auto& [lo, hi] : {std::pair{0, h / 3}, std::pair{h / 2, h / 2 + 6}, std::pair{h - 9, h}}) {
        Tensor f = banded_features(rng, h, w, lo, hi);
        const int minus_zero_row = lo > 4 ? lo - 4 : h - 3;
        f.at(0, 2, minus_zero_row, w / 2) = -0.0f;
        std::vector<int> band, empty, third = every_third_pixel(h * w);
        for (int p = 0; p < h * w; ++p) (p / w >= lo && p / w < hi ? band : empty).push_back(p);
        for (const std::vector<int>* pixels : {&band, &third, &empty, &band}) {
          const Tensor want = unfused(net, stats, f, *pixels);
          const Tensor& got = plan.run(f, *pixels);
          int differ = 0;
          for (int c = 0; c < 2; ++c)
            for (const int p : *pixels) {
              const std::size_t i = static_cast<std::size_t>(c * h * w + p);
              differ += bits(got[i]) != bits(want[i]);
            }
          EXPECT_EQ(differ, 0) << h << "x" << w << " deep " << deep << " band " << lo << ".." << hi << ", "
                               << pixels->size() << " pixels";
        }
      }
    }
  }
}

// run() with the caller's nonzero input rows (the feature builder's, instead of scanning the
// image for empty rows) gives the unfused path's bits, for the exact range and a wider one,
// alternating with scanning calls; a range that wrongly declares nonzero rows empty changes
// the output (the range is what the plan goes by). The pixel sets demand a part of the rows,
// so the flat layers compute one run of rows, not their whole output.
TEST(InferencePlan, GivenNonzeroInputRowsGiveTheScannedRunsBits) {
  for (const auto& [h, w] : {std::pair{61, 61}, std::pair{45, 38}}) {
    for (const bool deep : {false, true}) {
      Network net(deep ? deep_fast_arch() : test::fast_head_arch(true), Shape{1, 4, h, w});
      randomise(net, static_cast<std::uint64_t>(3 * h + w + deep));
      const ChannelStats stats = some_stats(4);
      InferencePlan plan(net, stats);
      Rng rng(13);
      for (const auto& [lo, hi] : {std::pair{0, h / 2}, std::pair{h / 3, h / 3 + 8}, std::pair{h - 12, h}}) {
        Tensor f = banded_features(rng, h, w, lo, hi);
        std::vector<int> band, lower;
        for (int p = 0; p < h * w; ++p) {
          if (p / w >= lo && p / w < hi && p % 3 == 0) band.push_back(p);
          if (p / w < h / 4) lower.push_back(p);
        }
        const InferencePlan::InputRows exact{lo, hi - 1}, wider{std::max(lo - 3, 0), std::min(hi + 2, h - 1)};
        for (const std::vector<int>* pixels : {&band, &lower, &band}) {
          const Tensor want = unfused(net, stats, f, *pixels);
          for (int call = 0; call < 3; ++call) {
            const Tensor& got = call == 0 ? plan.run(f, *pixels, exact) : call == 1 ? plan.run(f, *pixels) : plan.run(f, *pixels, wider);
            int differ = 0;
            for (int c = 0; c < 2; ++c)
              for (const int p : *pixels) {
                const std::size_t i = static_cast<std::size_t>(c * h * w + p);
                differ += bits(got[i]) != bits(want[i]);
              }
            EXPECT_EQ(differ, 0) << h << "x" << w << " deep " << deep << " band " << lo << ".." << hi << " call " << call
                                 << ", " << pixels->size() << " pixels";
          }
        }
        if (plan.fused()) {  // the unfused path ignores the range
          const Tensor want = unfused(net, stats, f, band);
          const Tensor& got = plan.run(f, band, InferencePlan::InputRows{1, 0});  // "every row +0"
          int differ = 0;
          for (int c = 0; c < 2; ++c)
            for (const int p : band) differ += bits(got[static_cast<std::size_t>(c * h * w + p)]) != bits(want[static_cast<std::size_t>(c * h * w + p)]);
          EXPECT_GT(differ, 0) << h << "x" << w << " deep " << deep << " band " << lo << ".." << hi
                               << ": every row declared empty";
        }
      }
    }
  }
}

TEST(InferencePlan, IsASnapshotOfTheWeights) {
  Network net(test::fast_head_arch(false), Shape{1, 3, 13, 11});
  randomise(net, 1);
  const ChannelStats stats = some_stats(3);
  Rng rng(4);
  Tensor f(1, 3, 13, 11);
  fill_gaussian(f, rng);
  const std::vector<int> pixels = every_third_pixel(13 * 11);
  InferencePlan plan(net, stats);
  const Tensor before = plan.run(f, pixels);
  const Tensor want = unfused(net, stats, f, pixels);
  randomise(net, 2);  // a fused plan keeps the weights it was built with
  const Tensor now = unfused(net, stats, f, pixels);
  const Tensor& again = plan.run(f, pixels);
  for (int c = 0; c < 2; ++c)
    for (const int p : pixels) {
      const std::size_t i = static_cast<std::size_t>(c * 13 * 11 + p);
      EXPECT_EQ(before[i], want[i]);
      EXPECT_EQ(again[i], plan.fused() ? want[i] : now[i]);  // the unfused path runs the network as it is
    }
  InferencePlan rebuilt(net, stats);  // a new plan sees the new weights
  const Tensor& fresh = rebuilt.run(f, pixels);
  for (const int p : pixels) EXPECT_EQ(fresh[static_cast<std::size_t>(p)], now[static_cast<std::size_t>(p)]);
  EXPECT_TRUE(plan.built_for(net));
}

TEST(InferencePlan, UnsupportedGraphsRunTheUnfusedPath) {
  // A separate ReLU node and a dense layer are not fused: the plan runs the unfused path.
  for (const char* text : {"name = \"r\"\n[[layer]]\ntype = \"conv\"\nout = 2\n[[layer]]\ntype = \"relu\"\n",
                           "name = \"d\"\n[[layer]]\ntype = \"dense\"\nout = 4\n"}) {
    Network net(ArchSpec::parse(text), Shape{1, 3, 5, 6});
    randomise(net, 5);
    const ChannelStats stats = some_stats(3);
    Rng rng(6);
    Tensor f(1, 3, 5, 6);
    fill_gaussian(f, rng);
    InferencePlan plan(net, stats);
    EXPECT_FALSE(plan.fused());
    EXPECT_EQ(plan.step_count(), 1u);
    EXPECT_EQ(plan.step_name(0), "network");
    const std::vector<int> pixels{0, 1};
    const Tensor want = unfused(net, stats, f, pixels);
    const Tensor& got = plan.run(f, pixels);
    ASSERT_EQ(got.shape(), want.shape());
    for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], want[i]);
  }
}

TEST(InferencePlan, RefusesBadInputs) {
  Network net(test::fast_head_arch(false), Shape{1, 3, 13, 11});
  randomise(net, 7);
  EXPECT_THROW(InferencePlan(net, some_stats(2)), InvalidArgument);
  InferencePlan plan(net, some_stats(3));
  Tensor wrong(1, 3, 11, 13);
  EXPECT_THROW((void)plan.run(wrong, std::vector<int>{0}), InvalidArgument);
  Tensor f(1, 3, 13, 11);
  EXPECT_THROW((void)plan.run(f, std::vector<int>{13 * 11}), InvalidArgument);
  EXPECT_THROW((void)plan.run(f, std::vector<int>{-1}), InvalidArgument);
}

}  // namespace
}  // namespace dc
