// Network graph: arch parsing/printing, shapes of the default U-Net, and a central-
// difference gradient check of a whole small encoder–decoder with skip connections,
// dropout and the weighted MSE loss.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/learning/arch.hpp"
#include "dc/learning/initializer.hpp"
#include "dc/learning/mse_loss.hpp"
#include "dc/learning/network.hpp"
#include "grad_check.hpp"
#include "small_archs.hpp"

namespace dc {
namespace {

using test::check_gradient;
using test::fill_gaussian;

TEST(Arch, DefaultUnetShapesAndSize) {
  Network net(default_arch(), Shape{1, 4, 61, 61});
  EXPECT_EQ(net.output_shape(), (Shape{1, 2, 61, 61}));
  // 4·16·9+16 + 16·32·9+32 + 32·32·9+32 + 64·32·9+32 + 48·16·9+16 + 16·2·9+2
  EXPECT_EQ(net.parameter_count(), 592u + 4640u + 9248u + 18464u + 6928u + 290u);
  Network net7(default_arch(), Shape{1, 7, 61, 61});
  EXPECT_EQ(net7.parameter_count(), net.parameter_count() + 3u * 16u * 9u);
  // Odd sizes mirror exactly: 61 → 31 → 16 → 31 → 61.
  const std::string s = net.summary();
  EXPECT_NE(s.find("u2: upsample x2 -> 31x31"), std::string::npos) << s;
  EXPECT_NE(s.find("u1: upsample x2 -> 61x61"), std::string::npos) << s;
}

TEST(Arch, SeedDenseHeadSize) {
  // 61×61 → 31 → 16 with 32 channels, dense 8192 → 2·61·61 = 7442.
  Network net(seed_dense_arch(), Shape{1, 4, 61, 61});
  EXPECT_EQ(net.output_shape(), (Shape{1, 2, 61, 61}));
  EXPECT_EQ(net.parameter_count(), 1184u + 9248u + 8192u * 7442u + 7442u);
}

TEST(Arch, TomlRoundTrip) {
  for (const ArchSpec& a : {default_arch(), seed_dense_arch(), default_arch(3, 0.25)}) {
    const std::string text = a.to_toml();
    const ArchSpec b = ArchSpec::parse(text, "roundtrip");
    EXPECT_EQ(b.to_toml(), text);
    ASSERT_EQ(b.layers.size(), a.layers.size());
    for (std::size_t i = 0; i < a.layers.size(); ++i) {
      EXPECT_EQ(b.layers[i].name, a.layers[i].name);
      EXPECT_EQ(b.layers[i].inputs, a.layers[i].inputs);
      EXPECT_EQ(b.layers[i].rate, a.layers[i].rate);
    }
  }
}

TEST(Arch, ParsesHandWrittenFileWithDefaults) {
  const ArchSpec a = ArchSpec::parse(R"(
name = "tiny"
[[layer]]
type = "conv"
out = 4
relu = true
[[layer]]
name = "down"
type = "conv"
out = 4
stride = 2
[[layer]]
type = "relu"
[[layer]]
name = "up"
type = "upsample"
size = [9, 9]
[[layer]]
type = "conv"
input = ["up", "layer0", "input"]
out = 2
kernel = 5
)");
  Network net(a, Shape{1, 3, 9, 9});
  EXPECT_EQ(net.output_shape(), (Shape{1, 2, 9, 9}));
  EXPECT_EQ(net.layer(4).describe(), "conv 11->2 k5 s1");
}

TEST(Arch, RejectsBadConfigsWithOneLineMessages) {
  auto bad = [](const std::string& text, const std::string& needle) {
    try {
      (void)ArchSpec::parse(text, "bad.toml");
      ADD_FAILURE() << "no error for: " << text;
    } catch (const ConfigError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(needle), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  };
  bad("[[layer]]\ntype = \"pool\"\n", "unknown layer type 'pool'");
  bad("[[layer]]\ntype = \"conv\"\nout = 4\nstrde = 2\n", "key 'strde'");
  bad("[[layer]]\ntype = \"conv\"\n", "key 'out'");
  bad("[[layer]]\ntype = \"conv\"\nout = 4\nkernel = 2\n", "key 'kernel'");
  bad("[[layer]]\ntype = \"relu\"\ninput = \"nope\"\n", "'nope' is not an earlier layer");
  bad("[[layer]]\nname = \"a\"\ntype = \"relu\"\n[[layer]]\nname = \"a\"\ntype = \"relu\"\n", "duplicate");
  bad("[[layer]]\ntype = \"dropout\"\nrate = 1.5\n", "key 'rate'");
  bad("name = 3\n", "key 'name'");
  bad("[[layer]\n", "bad.toml:1");
  // Shape errors surface when building for an input.
  const ArchSpec up = ArchSpec::parse("[[layer]]\ntype = \"upsample\"\nsize = [9, 9]\n");
  EXPECT_THROW(Network(up, Shape{1, 1, 3, 3}), ConfigError);
  const ArchSpec cat = ArchSpec::parse(
      "[[layer]]\nname = \"d\"\ntype = \"conv\"\nout = 2\nstride = 2\n[[layer]]\ntype = \"relu\"\ninput = [\"d\", \"input\"]\n");
  EXPECT_THROW(Network(cat, Shape{1, 1, 8, 8}), ConfigError);
}

TEST(NetworkGrad, EncoderDecoderWithSkipsAndWeightedMse) {
  // Small U-Net on 9×9: 9 → 5 → 3 → up 5 → concat → up 9 → concat (incl. the raw input)
  // → linear conv. Fused and stand-alone ReLUs and a dropout node are all on the path.
  const ArchSpec arch = ArchSpec::parse(R"(
name = "gradcheck-unet"
[[layer]]
name = "e1"
type = "conv"
out = 4
relu = true
[[layer]]
name = "e2"
type = "conv"
out = 5
stride = 2
[[layer]]
name = "e2r"
type = "relu"
[[layer]]
name = "e3"
type = "conv"
out = 6
stride = 2
relu = true
[[layer]]
name = "drop"
type = "dropout"
rate = 0.2
[[layer]]
name = "u2"
type = "upsample"
match = "e2"
[[layer]]
name = "d2"
type = "conv"
input = ["u2", "e2r"]
out = 5
relu = true
[[layer]]
name = "u1"
type = "upsample"
match = "e1"
[[layer]]
name = "d1"
type = "conv"
input = ["u1", "e1", "input"]
out = 4
relu = true
[[layer]]
name = "out"
type = "conv"
out = 2
)");
  Network net(arch, Shape{1, 3, 9, 9});
  Rng rng(101);
  net.initialize(HeNormal(), rng);
  for (ParamRef& p : net.parameters())
    if (!p.decay) fill_gaussian(*p.value, rng, 0.05);
  Tensor x(2, 3, 9, 9), t(2, 2, 9, 9), w(2, 1, 9, 9);
  fill_gaussian(x, rng);
  fill_gaussian(t, rng);
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = static_cast<float>(rng.uniform(0.0, 3.0));
  MseLoss mse;
  // Replaying the dropout stream from a fixed seed makes the mask part of the function.
  auto loss = [&](Tensor* grad) {
    Rng drop_rng(102);
    net.set_rng(&drop_rng);
    const double l = mse(net.forward(x, true), t, &w, grad);
    net.set_rng(nullptr);
    return l;
  };
  Tensor g;
  loss(&g);
  net.backward(g);
  std::vector<Tensor> grads;
  auto params = net.parameters();
  for (const ParamRef& p : params) grads.push_back(*p.grad);
  int checked = 0, bad = 0;
  for (std::size_t k = 0; k < params.size(); ++k) {
    // ε = 1e-3 keeps the chance of crossing a ReLU kink small; float rounding of a loss of
    // O(1) then limits agreement to ~1e-3, hence tolerance 2e-2 with ≤ 2 outliers per tensor.
    const auto st = check_gradient(params[k].name, *params[k].value, grads[k], [&] { return loss(nullptr); },
                                   1e-3, 2e-2, rng, 25, 2);
    checked += st.checked;
    bad += st.bad;
  }
  EXPECT_LE(bad, checked / 50) << bad << " of " << checked << " entries off";
  // Every parameter tensor received a non-zero gradient (all paths are connected).
  for (std::size_t k = 0; k < params.size(); ++k) EXPECT_GT(grads[k].flat().norm(), 0.0f) << params[k].name;
}



// Without ReLUs the network is linear in each parameter tensor, so central differences are
// exact up to float rounding: ε = 0.25, tolerance 1e-3 (the layer_gradcheck convention).
TEST(NetworkGrad, HalfResolutionUnetWithFullResolutionOneByOneHead) {
  Network net(test::fast_head_arch(false, false), Shape{1, 3, 11, 9});
  EXPECT_EQ(net.output_shape(), (Shape{1, 2, 11, 9}));
  Rng rng(111);
  net.initialize(HeNormal(), rng);
  for (ParamRef& p : net.parameters())
    if (!p.decay) fill_gaussian(*p.value, rng, 0.05);
  Tensor x(2, 3, 11, 9), t(2, 2, 11, 9);
  fill_gaussian(x, rng);
  fill_gaussian(t, rng);
  MseLoss mse;
  auto loss = [&](Tensor* grad) { return mse(net.forward(x, true), t, nullptr, grad); };
  Tensor g;
  loss(&g);
  net.backward(g);
  std::vector<Tensor> grads;
  auto params = net.parameters();
  for (const ParamRef& p : params) grads.push_back(*p.grad);
  int checked = 0, bad = 0;
  for (std::size_t k = 0; k < params.size(); ++k) {
    const auto st = check_gradient(params[k].name, *params[k].value, grads[k], [&] { return loss(nullptr); },
                                   0.25, 1e-3, rng, 25, 0);
    checked += st.checked;
    bad += st.bad;
  }
  EXPECT_EQ(bad, 0) << bad << " of " << checked << " entries off";
  for (std::size_t k = 0; k < params.size(); ++k) EXPECT_GT(grads[k].flat().norm(), 0.0f) << params[k].name;
}

// forward_at evaluates the 1×1 head (and the upsampling only it reads) at the listed pixels:
// the values there are forward()'s. Any other last layer falls back to forward().
TEST(NetworkForwardAt, SparseHeadEqualsTheDenseForwardAtTheListedPixels) {
  for (const bool relu : {false, true}) {
    Network net(test::fast_head_arch(relu), Shape{1, 3, 13, 11});
    Rng rng(7);
    net.initialize(HeNormal(), rng);
    for (ParamRef& p : net.parameters())
      if (!p.decay) fill_gaussian(*p.value, rng, 0.1);
    Tensor x(1, 3, 13, 11);
    fill_gaussian(x, rng);
    const Tensor dense = net.forward(x, false);
    const int P = 13 * 11;
    std::vector<int> pixels;
    for (int p = 0; p < P; p += 3) pixels.push_back(p);
    pixels.push_back(P - 1);  // the odd last row and column of the nearest upsampling
    Tensor sparse;
    EXPECT_TRUE(net.forward_at(x, pixels, sparse));
    ASSERT_EQ(sparse.shape(), dense.shape());
    for (int c = 0; c < 2; ++c)
      for (int p : pixels) {
        const float want = dense[static_cast<std::size_t>(c * P + p)];
        EXPECT_NEAR(sparse[static_cast<std::size_t>(c * P + p)], want, 1e-5f * (1.0f + std::abs(want)))
            << "relu " << relu << " channel " << c << " pixel " << p;
      }
    EXPECT_THROW(net.forward_at(x, std::vector<int>{P}, sparse), InvalidArgument);
  }
  // A 3×3 head: no sparse path, the dense forward.
  Network net(ArchSpec::parse("name = \"k3\"\n[[layer]]\ntype = \"conv\"\nout = 2\n"), Shape{1, 3, 7, 7});
  Rng rng(8);
  net.initialize(HeNormal(), rng);
  Tensor x(1, 3, 7, 7), y;
  fill_gaussian(x, rng);
  EXPECT_FALSE(net.forward_at(x, std::vector<int>{0, 5}, y));
  EXPECT_EQ(y.shape(), (Shape{1, 2, 7, 7}));
  const Tensor dense = net.forward(x, false);
  for (std::size_t i = 0; i < y.size(); ++i) EXPECT_EQ(y[i], dense[i]);
}

}  // namespace
}  // namespace dc
