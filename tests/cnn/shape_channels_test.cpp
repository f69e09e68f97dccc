// The shape channels of the feature image (coverage, orient_c, orient_s; docs/learning.md) on
// hand-made states: orientation of a box at 0, π/2, π, π/4, zero anisotropy of circles and
// regular polygons, coverage integrating to the body area, and the older channels unchanged.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "dc/cnn/feature_image.hpp"
#include "dc/cnn/shape_samples.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/shape.hpp"

namespace dc {
namespace {

constexpr double kPi = std::numbers::pi;

/// A builder with just the three shape channels (coverage, orient_c, orient_s).
FeatureImageBuilder shape_builder(double spacing = 0.5, double support = 0.5) {
  FeatureImageDef def = FeatureImageDef::for_box(30, 30);
  def.sph.grid.spacing = spacing;
  def.sph.support = support;
  def.channels = {FeatureChannel::Coverage, FeatureChannel::OrientC, FeatureChannel::OrientS};
  return FeatureImageBuilder(def);
}

std::vector<float> image_of(FeatureImageBuilder& b, const BodyState& s) {
  std::vector<float> img(b.feature_size());
  b.features(s, {}, img);
  return img;
}

BodyState one_body(const ShapeDef& shape, Vec2 x, double theta) {
  BodyState s;
  s.add_shaped(shape, Motion::Dynamic, x, 1.0, {}, theta);
  return s;
}

/// Σ coverage · d² over the grid: the covered area [m²].
double covered_area(const FeatureImageBuilder& b, std::span<const float> img) {
  double sum = 0;
  for (std::size_t p = 0; p < b.plane(); ++p) sum += img[p];
  return sum * b.def().sph.grid.spacing * b.def().sph.grid.spacing;
}

TEST(ShapeChannels, NamesParseBackAndTheOlderListsAreUnchanged) {
  for (const char* name : {"coverage", "orient_c", "orient_s"})
    EXPECT_EQ(to_string(parse_feature_channel(name)), std::string(name));
  EXPECT_EQ(parse_feature_channels("mass,coverage,orient_c,orient_s"),
            (std::vector<FeatureChannel>{FeatureChannel::Mass, FeatureChannel::Coverage, FeatureChannel::OrientC,
                                         FeatureChannel::OrientS}));
  // Old models and data sets name these lists; the new channels are not silently added.
  EXPECT_EQ(feature_channel_names(default_feature_channels()),
            (std::vector<std::string>{"mass", "vx", "vy", "omega", "contact_density"}));
  EXPECT_EQ(feature_channel_names(residual_feature_channels()),
            (std::vector<std::string>{"mass", "vx", "vy", "omega", "contact_density", "lambda_prev_n",
                                      "lambda_prev_t", "vrel_n", "vrel_t", "gap"}));
  EXPECT_THROW(parse_feature_channel("orientation"), ConfigError);
}

// A w × h box: Q = α (cos 2θ, sin 2θ), α = (w² − h²)/(w² + h²), at every node the box reaches
// (one body: the Shepard average is its own value).
TEST(ShapeChannels, BoxOrientationIsTheNematicOfItsLongAxis) {
  const double w = 1.5, h = 1.0, alpha = (w * w - h * h) / (w * w + h * h);
  const ShapeDef box = make_box({w, h}, "test box");
  FeatureImageBuilder b = shape_builder();
  const std::size_t P = b.plane();
  struct Case {
    double theta;
    Vec2 q;
  };
  for (const Case& c : {Case{0.0, {alpha, 0}}, Case{kPi / 2, {-alpha, 0}}, Case{kPi, {alpha, 0}},
                        Case{kPi / 4, {0, alpha}}, Case{-kPi / 4, {0, -alpha}}}) {
    const std::vector<float> img = image_of(b, one_body(box, {12.3, 17.6}, c.theta));
    int covered = 0;
    for (std::size_t p = 0; p < P; ++p) {
      if (img[p] <= 0) {
        EXPECT_EQ(img[P + p], 0.0f);  // no support: 0, not NaN
        EXPECT_EQ(img[2 * P + p], 0.0f);
        continue;
      }
      ++covered;
      EXPECT_NEAR(img[P + p], c.q.x, 1e-6) << "theta " << c.theta << " node " << p;
      EXPECT_NEAR(img[2 * P + p], c.q.y, 1e-6) << "theta " << c.theta << " node " << p;
    }
    EXPECT_GT(covered, 6) << "theta " << c.theta;  // the box spans several nodes, not one
  }
  // θ and θ + π are the same box: the whole image (coverage included) agrees.
  const std::vector<float> a = image_of(b, one_body(box, {12.3, 17.6}, 0.4));
  const std::vector<float> f = image_of(b, one_body(box, {12.3, 17.6}, 0.4 + kPi));
  for (std::size_t p = 0; p < a.size(); ++p) EXPECT_NEAR(a[p], f[p], 1e-5) << p;
  // The long axis along x vs along y: coverage differs (the shape is seen, not just the centre).
  const std::vector<float> x_long = image_of(b, one_body(box, {12.3, 17.6}, 0.0));
  const std::vector<float> y_long = image_of(b, one_body(box, {12.3, 17.6}, kPi / 2));
  double diff = 0;
  for (std::size_t p = 0; p < P; ++p) diff += std::abs(x_long[p] - y_long[p]);
  EXPECT_GT(diff, 0.1);
}

TEST(ShapeChannels, CirclesAndRegularPolygonsHaveNoOrientation) {
  FeatureImageBuilder b = shape_builder();
  const std::size_t P = b.plane();
  // A circle-only state (no shape table), a shaped circle, a hexagon and a square at odd angles.
  BodyState plain;
  plain.add({8.2, 9.1}, 0.7, 1.0, {}, 0.9);
  for (const BodyState& s : {plain, one_body(make_circle(0.7), {8.2, 9.1}, 0.9),
                             one_body(make_regular_polygon(6, 0.8, "hexagon"), {8.2, 9.1}, 0.37),
                             one_body(make_box({1.0, 1.0}, "square"), {8.2, 9.1}, 0.37)}) {
    EXPECT_EQ(body_frame_nematic(s, 0), (Vec2{0.0, 0.0}));
    const std::vector<float> img = image_of(b, s);
    EXPECT_TRUE(std::all_of(img.begin() + P, img.end(), [](float v) { return v == 0.0f; }));
    EXPECT_GT(*std::max_element(img.begin(), img.begin() + P), 0.0f);
  }
  // The circle-only path (no shape table) and the shaped circle splat the same disc.
  const std::vector<float> a = image_of(b, plain), c = image_of(b, one_body(make_circle(0.7), {8.2, 9.1}, 0.9));
  for (std::size_t p = 0; p < P; ++p) EXPECT_NEAR(a[p], c[p], 1e-6) << p;
  // An ellipse: α = (a² − b²)/(a² + b²) along its a axis.
  const BodyState e = one_body(make_ellipse({0.8, 0.4}, "ellipse"), {8.2, 9.1}, 0.0);
  EXPECT_NEAR(body_frame_nematic(e, 0).x, (0.64 - 0.16) / (0.64 + 0.16), 1e-12);
  EXPECT_NEAR(body_frame_nematic(e, 0).y, 0.0, 1e-12);
}

// ∫ coverage dA = body area (the kernel is 2D-normalised and the samples' weights sum to the
// area); on a grid with d ≪ h the node sum is that integral. Inside a body wider than 2h the
// coverage is the area fraction 1.
TEST(ShapeChannels, CoverageIntegratesToTheBodyArea) {
  FeatureImageBuilder b = shape_builder(0.05, 0.5);
  const std::vector<ShapeDef> shapes{make_box({1.5, 1.0}, "box"), make_box({3.0, 2.4}, "big box"),
                                     make_circle(0.6), make_ellipse({0.8, 0.4}, "ellipse"),
                                     make_regular_polygon(3, 0.7, "triangle"),
                                     make_polygon({{-0.6, -0.4}, {0.7, -0.5}, {0.5, 0.5}, {-0.4, 0.4}}, "quad")};
  for (const ShapeDef& shape : shapes) {
    const std::vector<float> img = image_of(b, one_body(shape, {14.13, 11.57}, 0.3));
    EXPECT_NEAR(covered_area(b, img), shape.area(), 0.01 * shape.area()) << shape_kind_name(shape.kind);
  }
  // Two bodies: areas add. A disc without a shape table: π r².
  BodyState two;
  two.add({5.0, 5.0}, 0.5, 1.0);
  two.add({20.0, 7.0}, 1.0, 1.0);
  EXPECT_NEAR(covered_area(b, image_of(b, two)), kPi * (0.25 + 1.0), 0.01 * kPi * 1.25);
  // The centre of the 3 × 2.4 box is ≥ h from its edges: area fraction 1.
  FeatureImageBuilder coarse = shape_builder();
  const std::vector<float> img = image_of(coarse, one_body(make_box({3.0, 2.4}, "big box"), {15.0, 15.0}, 0.0));
  const int ny = coarse.ny(), nx = coarse.nx();
  EXPECT_NEAR(img[static_cast<std::size_t>(30 * nx + 30)], 1.0, 0.05);
  EXPECT_EQ(ny, nx);
}

// Adding the shape channels to a list leaves every other channel bit-identical, and a polygon
// body's mass/velocity channels are still its centre splat.
TEST(ShapeChannels, OtherChannelsAreBitIdenticalWithOrWithoutTheShapeChannels) {
  BodyState s;
  s.add_shaped(make_box({1.5, 1.0}, "box"), Motion::Dynamic, {10.2, 3.3}, 1.0, {0.5, -1.0}, 0.6, 0.3);
  s.add_shaped(make_ellipse({0.8, 0.4}, "ellipse"), Motion::Dynamic, {11.9, 3.1}, 2.0, {-0.2, 0.1}, -1.1, 0.0);
  s.add_shaped(make_box({10.0, 0.4}, "plate"), Motion::Static, {15.0, 1.0}, 1.0, {}, 0.2);
  FeatureImageDef old_def = FeatureImageDef::for_box(30, 30);
  old_def.channels = residual_feature_channels();
  FeatureImageDef new_def = old_def;
  new_def.channels.insert(new_def.channels.begin() + 2, FeatureChannel::OrientS);
  new_def.channels.push_back(FeatureChannel::Coverage);
  new_def.channels.push_back(FeatureChannel::OrientC);
  FeatureImageBuilder ob(old_def), nb(new_def);
  std::vector<float> oi(ob.feature_size()), ni(nb.feature_size());
  ob.features(s, {}, oi);
  nb.features(s, {}, ni);
  const std::size_t P = ob.plane();
  for (std::size_t c = 0; c < old_def.channels.size(); ++c) {
    const auto at = std::find(new_def.channels.begin(), new_def.channels.end(), old_def.channels[c]);
    const std::size_t nc = static_cast<std::size_t>(at - new_def.channels.begin());
    EXPECT_TRUE(std::equal(oi.begin() + c * P, oi.begin() + (c + 1) * P, ni.begin() + nc * P))
        << to_string(old_def.channels[c]);
  }
  // The static plate is covered too (contacts happen there), with the orientation of its long
  // axis: 3 m from its centre along the axis, α = (100 − 0.16)/(100 + 0.16), 2θ = 0.4.
  const std::size_t cov = new_def.channels.size() - 2, oc = cov + 1, os = 2;
  const double px = 15.0 + 3 * std::cos(0.2), py = 1.0 + 3 * std::sin(0.2), alpha = 99.84 / 100.16;
  const std::size_t node = static_cast<std::size_t>(std::lround(py / 0.5)) * nb.nx() + std::lround(px / 0.5);
  EXPECT_GT(ni[cov * P + node], 0.5f);
  EXPECT_NEAR(ni[oc * P + node], alpha * std::cos(0.4), 1e-5);
  EXPECT_NEAR(ni[os * P + node], alpha * std::sin(0.4), 1e-5);
}

TEST(ShapeChannels, SamplesSumToTheAreaAndHaveZeroFirstMoment) {
  for (const ShapeDef& shape : {make_box({1.5, 1.0}, "box"), make_ellipse({0.8, 0.4}, "ellipse"), make_circle(0.5),
                                make_box({10.0, 0.4}, "plate")}) {
    const BodyState s = one_body(shape, {5, 5}, 0.0);
    for (double spacing : {0.05, 0.25, 10.0}) {
      std::vector<AreaSample> out;
      append_area_samples(s, 0, spacing, out);
      double area = 0;
      Vec2 first{};
      for (const AreaSample& a : out) {
        area += a.area;
        first += a.area * a.point;
      }
      EXPECT_NEAR(area, shape.area(), 1e-12 * shape.area()) << shape_kind_name(shape.kind) << " " << spacing;
      EXPECT_NEAR(first.x, 0.0, 1e-12);
      EXPECT_NEAR(first.y, 0.0, 1e-12);
      // Finer spacing ⇒ more samples, all inside the bounding radius.
      for (const AreaSample& a : out) EXPECT_LE(length(a.point), shape.radius + 1e-12);
    }
  }
  std::vector<AreaSample> out;
  EXPECT_THROW(append_area_samples(one_body(make_circle(1.0), {5, 5}, 0.0), 0, 0.0, out), InvalidArgument);
}

}  // namespace
}  // namespace dc
