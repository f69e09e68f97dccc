// Central-difference gradient checks of every layer: input gradients and parameter
// gradients. Piecewise-linear layers without kinks near the sample point are exactly
// linear there, so a large step (ε = 0.25) leaves only float rounding and the tolerance
// can be tight (1e-3); layers with ReLU use ε = 1e-3 on inputs kept away from 0.
#include <cstring>

#include <gtest/gtest.h>
#include <omp.h>

#include "dc/core/error.hpp"
#include "dc/learning/initializer.hpp"
#include "dc/learning/layers/concat.hpp"
#include "dc/learning/layers/conv2d.hpp"
#include "dc/learning/layers/dense.hpp"
#include "dc/learning/layers/dropout.hpp"
#include "dc/learning/layers/relu.hpp"
#include "dc/learning/layers/upsample.hpp"
#include "dc/learning/mse_loss.hpp"
#include "grad_check.hpp"

namespace dc {
namespace {

using test::check_gradient;
using test::fill_gaussian;
using test::probe;

// Full check of a layer at input x: dL/dx and dL/dθ for L = Σ r ⊙ f(x).
void check_layer(Layer& layer, Tensor x, double eps, double tol, std::uint64_t seed, int max_bad = 0) {
  Rng rng(seed);
  Tensor y;
  layer.forward(x, y, false);
  Tensor r(y.shape());
  fill_gaussian(r, rng);
  Tensor dx;
  layer.backward(x, y, r, &dx);
  ASSERT_EQ(dx.shape(), x.shape());
  // Copy the analytic parameter gradients before the loss closure reruns forward.
  std::vector<Tensor> grads;
  for (const ParamRef& p : layer.parameters()) grads.push_back(*p.grad);
  auto loss = [&] {
    Tensor yy;
    layer.forward(x, yy, false);
    return probe(yy, r);
  };
  check_gradient(layer.describe() + " dx", x, dx, loss, eps, tol, rng, 60, max_bad);
  auto params = layer.parameters();
  for (std::size_t k = 0; k < params.size(); ++k)
    check_gradient(layer.describe() + " d" + params[k].name, *params[k].value, grads[k], loss, eps, tol, rng, 60,
                   max_bad);
}

void init_layer(Layer& layer, std::uint64_t seed) {
  Rng rng(seed);
  layer.initialize(HeNormal(), rng);
  for (const ParamRef& p : layer.parameters())
    if (!p.decay) fill_gaussian(*p.value, rng, 0.1);  // non-zero biases so db is exercised
}

struct ConvCase {
  int cin, cout, k, s, h, w, n;
};

class ConvGrad : public ::testing::TestWithParam<ConvCase> {};

TEST_P(ConvGrad, LinearConvMatchesCentralDifferences) {
  const ConvCase c = GetParam();
  Conv2d conv(c.cin, c.cout, c.k, c.s, false);
  init_layer(conv, 11);
  Tensor x(c.n, c.cin, c.h, c.w);
  Rng rng(12);
  fill_gaussian(x, rng);
  const Shape out = conv.output_shape(x.shape());
  EXPECT_EQ(out.h, (c.h + c.s - 1) / c.s);
  EXPECT_EQ(out.w, (c.w + c.s - 1) / c.s);
  check_layer(conv, x, 0.25, 1e-3, 13);
}

INSTANTIATE_TEST_SUITE_P(Shapes, ConvGrad,
                         ::testing::Values(ConvCase{3, 4, 3, 1, 7, 9, 2}, ConvCase{3, 5, 3, 2, 9, 7, 2},
                                           ConvCase{2, 3, 3, 2, 8, 8, 3}, ConvCase{2, 3, 5, 1, 6, 7, 1},
                                           ConvCase{1, 2, 1, 1, 5, 5, 2}, ConvCase{2, 2, 3, 3, 10, 11, 2},
                                           ConvCase{4, 16, 3, 2, 61, 61, 1}));

TEST(ConvGrad, FusedReluMatchesCentralDifferences) {
  // A weight step moves every pre-activation of its output channel, so with ~100 of them
  // one may sit within the step of a kink; allow 2 such entries out of ~130 checked.
  Conv2d conv(3, 4, 3, 1, true);
  init_layer(conv, 21);
  Tensor x(2, 3, 8, 7);
  Rng rng(22);
  fill_gaussian(x, rng);
  check_layer(conv, x, 2e-4, 1e-2, 23, 2);
}

TEST(ConvGrad, FusedReluEqualsConvThenRelu) {
  // Exact relationship: conv(relu=true) must give the same y, dx, dW, db as
  // conv(relu=false) followed by a ReLU layer (both checked strictly above).
  Conv2d fused(3, 5, 3, 2, true), plain(3, 5, 3, 2, false);
  init_layer(fused, 24);
  init_layer(plain, 24);
  ReLU relu;
  Tensor x(3, 3, 9, 8);
  Rng rng(25);
  fill_gaussian(x, rng);
  Tensor yf, z, yp, r, dxf, dz, dxp;
  fused.forward(x, yf, false);
  plain.forward(x, z, false);
  relu.forward(z, yp, false);
  r.resize(yf.shape());
  fill_gaussian(r, rng);
  fused.backward(x, yf, r, &dxf);
  relu.backward(z, yp, r, &dz);
  plain.backward(x, z, dz, &dxp);
  for (std::size_t i = 0; i < yf.size(); ++i) ASSERT_EQ(yf[i], yp[i]);
  for (std::size_t i = 0; i < dxf.size(); ++i) ASSERT_NEAR(dxf[i], dxp[i], 1e-6);
  for (std::size_t i = 0; i < fused.weight().size(); ++i)
    ASSERT_NEAR(fused.parameters()[0].grad->data()[i], plain.parameters()[0].grad->data()[i], 1e-5);
  for (int o = 0; o < 5; ++o)
    ASSERT_NEAR(fused.parameters()[1].grad->data()[o], plain.parameters()[1].grad->data()[o], 1e-5);
}

TEST(ConvGrad, MatchesDirectConvolution) {
  // Independent check of the forward against the defining sum (catches a transposed
  // kernel or mis-centred padding, which a gradient check alone would not).
  Conv2d conv(2, 3, 3, 2, false);
  init_layer(conv, 31);
  Tensor x(1, 2, 7, 6);
  Rng rng(32);
  fill_gaussian(x, rng);
  Tensor y;
  conv.forward(x, y, false);
  ASSERT_EQ(y.shape(), (Shape{1, 3, 4, 3}));
  // Ho = 4: total pad = (4−1)·2 + 3 − 7 = 2 → top 1; Wo = 3: (3−1)·2 + 3 − 6 = 1 → left 0.
  for (int o = 0; o < 3; ++o)
    for (int oy = 0; oy < 4; ++oy)
      for (int ox = 0; ox < 3; ++ox) {
        double s = conv.bias()[o];
        for (int c = 0; c < 2; ++c)
          for (int ky = 0; ky < 3; ++ky)
            for (int kx = 0; kx < 3; ++kx) {
              const int iy = oy * 2 + ky - 1, ix = ox * 2 + kx - 0;
              if (iy < 0 || iy >= 7 || ix < 0 || ix >= 6) continue;
              s += double(conv.weight()(o, c, ky, kx)) * x(0, c, iy, ix);
            }
        EXPECT_NEAR(y(0, o, oy, ox), s, 1e-5) << o << " " << oy << " " << ox;
      }
}

TEST(ConvGrad, ResultsDoNotDependOnTheThreadCount) {
  // Work groups depend on the batch size only and are summed in group order, so 1 and 2
  // threads must agree bit for bit (batch 1 exercises the tile split, incl. the shared
  // dX_col of stride 2; batch 5 the sample groups).
  for (int stride : {1, 2})
    for (int batch : {1, 5}) {
      Conv2d conv(8, 12, 3, stride, true);
      init_layer(conv, 33);
      Tensor x(batch, 8, 31, 29);
      Rng rng(34);
      fill_gaussian(x, rng);
      auto run = [&](int threads, Tensor& y, Tensor& dx, Tensor& dw) {
        const int saved = omp_get_max_threads();
        omp_set_num_threads(threads);
        conv.forward(x, y, false);
        Tensor r(y.shape());
        Rng rr(35);
        fill_gaussian(r, rr);
        conv.backward(x, y, r, &dx);
        dw = *conv.parameters()[0].grad;
        omp_set_num_threads(saved);
      };
      Tensor y1, dx1, dw1, y2, dx2, dw2;
      run(1, y1, dx1, dw1);
      run(2, y2, dx2, dw2);
      EXPECT_EQ(std::memcmp(y1.data(), y2.data(), sizeof(float) * y1.size()), 0) << stride << " " << batch;
      EXPECT_EQ(std::memcmp(dx1.data(), dx2.data(), sizeof(float) * dx1.size()), 0) << stride << " " << batch;
      EXPECT_EQ(std::memcmp(dw1.data(), dw2.data(), sizeof(float) * dw1.size()), 0) << stride << " " << batch;
    }
}

TEST(ConvGrad, RejectsWrongChannelCount) {
  Conv2d conv(3, 4);
  Tensor x(1, 2, 5, 5), y;
  EXPECT_THROW(conv.forward(x, y, false), InvalidArgument);
  EXPECT_THROW(Conv2d(3, 4, 2), InvalidArgument);
}

TEST(ReluGrad, MatchesCentralDifferences) {
  ReLU relu;
  Tensor x(2, 3, 4, 5);
  Rng rng(41);
  fill_gaussian(x, rng, 1.0, 0.05);  // keep |x| ≥ 0.05 > ε: no kink crossed
  check_layer(relu, x, 1e-2, 1e-3, 42);
}

TEST(DenseGrad, LinearMatchesCentralDifferences) {
  Dense dense(2 * 3 * 4, Shape{1, 2, 3, 3}, false);
  init_layer(dense, 51);
  Tensor x(3, 2, 3, 4);
  Rng rng(52);
  fill_gaussian(x, rng);
  check_layer(dense, x, 0.25, 1e-3, 53);
}

TEST(DenseGrad, FusedReluMatchesCentralDifferences) {
  Dense dense(12, Shape{1, 7, 1, 1}, true);
  init_layer(dense, 54);
  Tensor x(4, 3, 2, 2);
  Rng rng(55);
  fill_gaussian(x, rng);
  check_layer(dense, x, 1e-3, 1e-2, 56);
}

TEST(UpsampleGrad, OddAndEvenTargets) {
  for (auto [h, w, ho, wo] : {std::array{16, 16, 31, 31}, std::array{31, 31, 61, 61}, std::array{3, 4, 6, 7},
                              std::array{5, 5, 0, 0}}) {
    Upsample2x up(ho, wo);
    Tensor x(2, 2, h, w);
    Rng rng(61);
    fill_gaussian(x, rng);
    Tensor y;
    up.forward(x, y, false);
    EXPECT_EQ(y.h(), ho ? ho : 2 * h);
    EXPECT_EQ(y(1, 1, y.h() - 1, y.w() - 1), x(1, 1, (y.h() - 1) / 2, (y.w() - 1) / 2));
    check_layer(up, x, 0.25, 1e-4, 62);
  }
  EXPECT_THROW((void)Upsample2x(33, 33).output_shape({1, 1, 16, 16}), InvalidArgument);
}

TEST(UpsampleGrad, BackwardIsExactAdjoint) {
  // <up(x), g> = <x, upᵀ(g)> in exact arithmetic; with small integers it is exact in float.
  Upsample2x up(31, 29);
  Tensor x(1, 2, 16, 15), g(1, 2, 31, 29);
  Rng rng(63);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = float(rng.uniform_int(7)) - 3.0f;
  for (std::size_t i = 0; i < g.size(); ++i) g[i] = float(rng.uniform_int(7)) - 3.0f;
  Tensor y, dx;
  up.forward(x, y, false);
  up.backward(x, y, g, &dx);
  EXPECT_EQ(probe(y, g), probe(x, dx));
}

TEST(DropoutGrad, MaskIsFixedForAFixedSeed) {
  Tensor x(2, 3, 6, 6);
  Rng rng(71);
  fill_gaussian(x, rng);
  // Re-seeding before every forward replays the same mask, so the layer is a fixed linear
  // map inside the loss closure and the central difference is exact up to rounding.
  Dropout drop(0.3);
  auto fwd = [&](Tensor& y) {
    Rng r(72);
    drop.set_rng(&r);
    drop.forward(x, y, true);
    drop.set_rng(nullptr);
  };
  Tensor y;
  fwd(y);
  Tensor r(y.shape());
  fill_gaussian(r, rng);
  Tensor dx;
  drop.backward(x, y, r, &dx);
  check_gradient("dropout dx", x, dx, [&] { Tensor yy; fwd(yy); return probe(yy, r); }, 0.25, 1e-4, rng);
  // Inverted dropout: kept entries scaled by 1/(1−p), dropped ones zero; about p dropped.
  int dropped = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    if (y[i] == 0.0f) ++dropped;
    else EXPECT_FLOAT_EQ(y[i], x[i] / 0.7f);
  }
  EXPECT_NEAR(double(dropped) / y.size(), 0.3, 0.08);
  // Inference is the identity, and training without an Rng is an error.
  drop.forward(x, y, false);
  for (std::size_t i = 0; i < y.size(); ++i) EXPECT_EQ(y[i], x[i]);
  EXPECT_THROW(drop.forward(x, y, true), InvalidArgument);
}

TEST(ConcatGrad, SplitIsAdjointOfConcat) {
  Tensor a(2, 3, 4, 5), b(2, 1, 4, 5), y;
  Rng rng(81);
  fill_gaussian(a, rng);
  fill_gaussian(b, rng);
  const Tensor* ins[] = {&a, &b};
  concat_channels(ins, y);
  ASSERT_EQ(y.shape(), (Shape{2, 4, 4, 5}));
  EXPECT_EQ(y(1, 3, 2, 1), b(1, 0, 2, 1));
  EXPECT_EQ(y(1, 2, 3, 4), a(1, 2, 3, 4));
  Tensor r(y.shape());
  fill_gaussian(r, rng);
  Tensor da(a.shape()), db(b.shape());
  Tensor* gs[] = {&da, &db};
  const bool acc[] = {false, false};
  split_channels(r, gs, acc);
  auto loss = [&] { Tensor yy; concat_channels(ins, yy); return probe(yy, r); };
  check_gradient("concat da", a, da, loss, 0.25, 1e-4, rng);
  check_gradient("concat db", b, db, loss, 0.25, 1e-4, rng);
  Tensor bad(2, 1, 4, 4);
  const Tensor* ins_bad[] = {&a, &bad};
  EXPECT_THROW(concat_channels(ins_bad, y), InvalidArgument);
}

TEST(MseLossGrad, WeightedAndSharedWeights) {
  Rng rng(91);
  Tensor p(2, 2, 3, 4), t(2, 2, 3, 4), w(2, 2, 3, 4), w1(2, 1, 3, 4);
  fill_gaussian(p, rng);
  fill_gaussian(t, rng);
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = static_cast<float>(rng.uniform(0.0, 2.0));
  for (std::size_t i = 0; i < w1.size(); ++i) w1[i] = static_cast<float>(rng.uniform(0.0, 2.0));
  MseLoss mse;
  for (const Tensor* wt : std::vector<const Tensor*>{nullptr, &w, &w1}) {
    Tensor g;
    mse(p, t, wt, &g);
    // The loss is quadratic: central differences are exact up to rounding for any ε.
    check_gradient("mse dp", p, g, [&] { return mse(p, t, wt); }, 0.1, 1e-4, rng);
  }
  // Unweighted = plain mean; weight 0/1 mask = mean over the kept elements.
  double s = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) s += (double(p[i]) - t[i]) * (double(p[i]) - t[i]);
  EXPECT_NEAR(mse(p, t), s / p.size(), 1e-12);
  Tensor mask(p.shape());
  mask[5] = 1.0f;
  EXPECT_NEAR(mse(p, t, &mask), (double(p[5]) - t[5]) * (double(p[5]) - t[5]), 1e-12);
  Tensor wrong(1, 2, 3, 4);
  EXPECT_THROW(mse(p, t, &wrong), InvalidArgument);
}

}  // namespace
}  // namespace dc
