// Feature and label images: orientation (asymmetric single body / single contact), Shepard
// fields, units, channel selection, and label → gather == the sph warm starter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "dc/cnn/feature_image.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/world.hpp"
#include "dc/learning/arch.hpp"
#include "dc/learning/model.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/sph_warm_starter.hpp"
#include "dc/sph/sph_transfer.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "settled_pile.hpp"

namespace dc {
namespace {

/// (j, i) of the largest value of channel c.
std::pair<int, int> argmax(std::span<const float> img, int c, int ny, int nx) {
  const float* p = img.data() + static_cast<std::size_t>(c) * ny * nx;
  const auto k = std::max_element(p, p + static_cast<std::size_t>(ny) * nx) - p;
  return {static_cast<int>(k / nx), static_cast<int>(k % nx)};
}

float at(std::span<const float> img, int c, int j, int i, int ny, int nx) {
  return img[(static_cast<std::size_t>(c) * ny + j) * nx + i];
}

TEST(FeatureImage, DefaultGridFollowsTheSphSettingAndChannelsAreDocumented) {
  const FeatureImageBuilder b(FeatureImageDef::for_box(30, 30));
  const SphTransferDef sph = default_sph_setting(30, 30);
  EXPECT_EQ(b.def().sph.kernel, sph.kernel);
  EXPECT_EQ(b.def().sph.support, sph.support);
  EXPECT_EQ(b.def().sph.grid.spacing, sph.grid.spacing);
  EXPECT_EQ(b.nx(), sph_node_count(30, sph.grid.spacing));
  EXPECT_EQ(b.ny(), sph_node_count(30, sph.grid.spacing));
  const auto names = feature_channel_names(default_feature_channels());
  EXPECT_EQ(names, (std::vector<std::string>{"mass", "vx", "vy", "omega", "contact_density"}));
  EXPECT_EQ(label_channel_names(), (std::vector<std::string>{"lambda_n", "lambda_t"}));
  // Every channel name parses back to its channel (the residual set covers the new ones).
  for (FeatureChannel c : residual_feature_channels()) EXPECT_EQ(parse_feature_channel(to_string(c)), c);
  for (FeatureChannel c : {FeatureChannel::Nx, FeatureChannel::Ny}) EXPECT_EQ(parse_feature_channel(to_string(c)), c);
  EXPECT_EQ(parse_feature_channels("gap, lambda_prev_n,vrel_t"),
            (std::vector<FeatureChannel>{FeatureChannel::Gap, FeatureChannel::LambdaPrevN, FeatureChannel::VrelT}));
}

TEST(FeatureImage, AsymmetricSingleBodyPinsAxesAndShepardFieldsReturnTheBodyValues) {
  FeatureImageBuilder b(FeatureImageDef::for_box(30, 30));
  const double d = b.def().sph.grid.spacing;
  BodyState s;
  s.add({3.2, 7.9}, 1.0, 2.0, {1.5, -2.5}, 0.3, 0.7);
  std::vector<float> img(b.feature_size());
  b.features(s, {}, img);
  const int ny = b.ny(), nx = b.nx();
  const auto [j, i] = argmax(img, 0, ny, nx);
  EXPECT_EQ(j, static_cast<int>(std::lround(7.9 / d)));  // row = y
  EXPECT_EQ(i, static_cast<int>(std::lround(3.2 / d)));  // column = x
  // Shepard fields: exactly the body's values wherever the kernel reaches, 0 elsewhere.
  EXPECT_NEAR(at(img, 1, j, i, ny, nx), 1.5f, 1e-6);
  EXPECT_NEAR(at(img, 2, j, i, ny, nx), -2.5f, 1e-6);
  EXPECT_NEAR(at(img, 3, j, i, ny, nx), 0.7f, 1e-6);
  EXPECT_EQ(at(img, 1, i, j, ny, nx), 0.0f);  // the transposed node is far away
  EXPECT_EQ(at(img, 0, i, j, ny, nx), 0.0f);
  // Mass density: Σ_k W m_k at the nearest node equals W(|node − x|) m.
  const SphKernel W(b.def().sph.kernel, b.def().sph.support);
  const double r = std::hypot(i * d - 3.2, j * d - 7.9);
  EXPECT_NEAR(at(img, 0, j, i, ny, nx), W(r) * s.mass[0], 1e-5 * W(r) * s.mass[0]);
  // No contacts ⇒ contact density 0 everywhere.
  for (std::size_t p = 0; p < b.plane(); ++p) EXPECT_EQ(img[4 * b.plane() + p], 0.0f);
}

TEST(FeatureImage, MassChannelIsADensityThatIntegratesToTheMass) {
  FeatureImageDef def = FeatureImageDef::for_box(10, 10);
  def.sph.grid.spacing = 0.05;  // d ≪ h: Σ G d² → m
  def.sph.support = 0.5;
  def.channels = {FeatureChannel::Mass};
  FeatureImageBuilder b(def);
  BodyState s;
  s.add({4.03, 6.71}, 1.0, 1.0);
  std::vector<float> img(b.feature_size());
  b.features(s, {}, img);
  double sum = 0;
  for (float v : img) sum += v;
  EXPECT_NEAR(sum * 0.05 * 0.05, s.mass[0], 0.01 * s.mass[0]);
}

TEST(FeatureImage, ContactChannelsAndChannelOrder) {
  FeatureImageDef def = FeatureImageDef::for_box(30, 30);
  def.channels = {FeatureChannel::Ny, FeatureChannel::ContactDensity, FeatureChannel::Nx};
  FeatureImageBuilder b(def);
  const double d = def.sph.grid.spacing;
  Contact c;
  c.point = {20.3, 4.1};
  c.normal = {0.6, 0.8};
  std::vector<Contact> cs{c};
  BodyState none;
  std::vector<float> img(b.feature_size());
  b.features(none, cs, img);
  const int ny = b.ny(), nx = b.nx();
  const auto [j, i] = argmax(img, 1, ny, nx);
  EXPECT_EQ(j, static_cast<int>(std::lround(4.1 / d)));
  EXPECT_EQ(i, static_cast<int>(std::lround(20.3 / d)));
  EXPECT_NEAR(at(img, 0, j, i, ny, nx), 0.8f, 1e-6);  // channel 0 is ny
  EXPECT_NEAR(at(img, 2, j, i, ny, nx), 0.6f, 1e-6);  // channel 2 is nx
}

// Per-contact channels: the previous λ matched by key (0 for a new contact), the relative
// velocity of the contact points (with the ω × r terms, wall at rest) and the gap, all as
// Shepard numerators at the contact point, so label − lambda_prev = splat(λ* − λ_prev).
TEST(FeatureImage, PerContactChannelsAreNumeratorsOfBuiltinLambdaRelativeVelocityAndGap) {
  FeatureImageDef def = FeatureImageDef::for_box(30, 30);
  def.channels = {FeatureChannel::LambdaPrevN, FeatureChannel::LambdaPrevT, FeatureChannel::VrelN,
                  FeatureChannel::VrelT, FeatureChannel::Gap};
  FeatureImageBuilder b(def);
  const double d = def.sph.grid.spacing;
  const SphKernel W(def.sph.kernel, def.sph.support);
  // Body 0 at (20.3, 5.1) with a floor contact at (20.3, 4.1) below it (r = 1); bodies 1 and 2
  // at (6, 21.2) and (8, 21.2) touching at (7, 21.2), normal +x (from 1 to 2).
  BodyState s;
  auto add = [&](Vec2 x, Vec2 v, double w) { s.add(x, 1.0, 1.0, v, 0.0, w); };
  add({20.3, 5.1}, {0.5, -2.0}, 3.0);
  add({6.0, 21.2}, {1.0, 0.25}, 0.0);
  add({8.0, 21.2}, {-1.0, 0.75}, -2.0);
  Contact floor;  // wall a = bottom, b = body 0; normal from the wall into the body
  floor.key = ContactKey::wall(Wall::Bottom, 0);
  floor.body_a = static_cast<int>(Wall::Bottom);
  floor.body_b = 0;
  floor.point = {20.3, 4.1};
  floor.normal = {0, 1};
  floor.gap = -0.02;
  Contact pair;
  pair.key = ContactKey::pair(1, 2);
  pair.body_a = 1;
  pair.body_b = 2;
  pair.point = {7.0, 21.2};
  pair.normal = {1, 0};
  pair.gap = 0.01;
  const std::vector<Contact> cur{floor, pair};  // key order: wall contacts first
  Contact old_floor = floor;                   // persists, with last step's λ
  old_floor.lambda_n = 30.0;
  old_floor.lambda_t = -4.0;
  Contact gone;  // a contact that does not persist
  gone.key = ContactKey::pair(0, 2);
  gone.lambda_n = 99;
  const std::vector<Contact> prev{old_floor, gone};
  std::vector<float> img(b.feature_size());
  b.features(s, cur, prev, img);
  const int ny = b.ny(), nx = b.nx();

  // Floor contact: node nearest (20.3, 4.1).
  int j = static_cast<int>(std::lround(4.1 / d)), i = static_cast<int>(std::lround(20.3 / d));
  double w = W(std::hypot(i * d - 20.3, j * d - 4.1));
  ASSERT_GT(w, 0);
  // u_b at the point: v + ω × r with r = (0, −1): ω × r = (−ω r_y, ω r_x) = (3, 0) → (3.5, −2).
  EXPECT_NEAR(at(img, 0, j, i, ny, nx), w * 30.0, 1e-5 * w * 30);
  EXPECT_NEAR(at(img, 1, j, i, ny, nx), w * -4.0, 1e-5 * w * 4);
  EXPECT_NEAR(at(img, 2, j, i, ny, nx), w * -2.0, 1e-5 * w * 2);  // vrel_n = u·n = −2 (approaching)
  EXPECT_NEAR(at(img, 3, j, i, ny, nx), w * -3.5, 1e-5 * w * 3.5);  // t = perp(n) = (−1, 0)
  EXPECT_NEAR(at(img, 4, j, i, ny, nx), w * -0.02, 1e-5);

  // Pair contact: new (λ_prev = 0). u_b − u_a: body 2 at r = (−1, 0): (−1, 0.75) + (0, −2·−1)
  // = (−1, 2.75); body 1 at r = (1, 0), ω = 0: (1, 0.25). Difference (−2, 2.5): n = (1, 0),
  // t = (0, 1) → vrel_n = −2, vrel_t = 2.5.
  j = static_cast<int>(std::lround(21.2 / d));
  i = static_cast<int>(std::lround(7.0 / d));
  w = W(std::hypot(i * d - 7.0, j * d - 21.2));
  ASSERT_GT(w, 0);
  EXPECT_EQ(at(img, 0, j, i, ny, nx), 0.0f);
  EXPECT_EQ(at(img, 1, j, i, ny, nx), 0.0f);
  EXPECT_NEAR(at(img, 2, j, i, ny, nx), w * -2.0, 1e-5 * w * 2);
  EXPECT_NEAR(at(img, 3, j, i, ny, nx), w * 2.5, 1e-5 * w * 2.5);
  EXPECT_NEAR(at(img, 4, j, i, ny, nx), w * 0.01, 1e-6);

  // Without previous contacts every contact is new: the lambda_prev channels vanish.
  b.features(s, cur, img);
  EXPECT_TRUE(std::all_of(img.begin(), img.begin() + 2 * ny * nx, [](float v) { return v == 0.0f; }));
  // Unsorted contact lists are refused (the key matching is a merge).
  const std::vector<Contact> unsorted{pair, floor};
  EXPECT_THROW(b.features(s, unsorted, prev, img), InvalidArgument);
}

// On a real step, label − lambda_prev (numerators) read back at the contacts is λ* − λ_prev:
// the residual target decodes to the correction the cnn starter adds to builtin.
// contact_weights(): the kernel-weight field S of the contact points, bit for bit what
// SphTransfer::gather splats for the Shepard read-back (the cnn starter reuses it), whichever
// splat produced it (alone, with the normals, or with the per-contact values); the
// contact_density channel is S in float; null without a contact channel.
TEST(FeatureImage, ContactWeightsAreTheReadBacksShepardDenominatorBitForBit) {
  WorldDef wd;
  wd.bodies.count = 40;
  wd.bodies.seed = 5;
  World world(wd);
  (void)test::step_then_assemble(world, 150, 50);
  ASSERT_GT(world.contacts().size(), 10u);
  std::vector<Vec2> points;
  for (const Contact& c : world.contacts()) points.push_back(c.point);
  const FeatureImageDef base = FeatureImageDef::for_box(wd.world.width, wd.world.height);
  SphTransferDef t = base.sph;
  t.grid.channels = 2;
  t.normalisation = SphNormalisation::Shepard;
  SphTransfer transfer(t);
  (void)transfer.gather(SphGrid(t.grid), points);
  const std::span<const double> want = transfer.weights().data();
  using C = FeatureChannel;
  const std::vector<std::vector<C>> sets = {
      {C::Mass, C::ContactDensity},
      {C::ContactDensity, C::Nx, C::Ny},
      {C::Mass, C::Vx, C::Vy, C::Omega, C::ContactDensity, C::LambdaPrevN, C::LambdaPrevT, C::VrelN, C::VrelT, C::Gap},
      {C::Mass, C::LambdaPrevN}};
  for (const std::vector<C>& channels : sets) {
    FeatureImageDef def = base;
    def.channels = channels;
    FeatureImageBuilder b(def);
    std::vector<float> img(b.feature_size());
    b.features(world.bodies(), world.contacts(), world.previous_contacts(), img);
    const auto density = std::find(channels.begin(), channels.end(), C::ContactDensity);
    if (density == channels.end()) {
      EXPECT_EQ(b.contact_weights(), nullptr);
      continue;
    }
    ASSERT_NE(b.contact_weights(), nullptr) << channels.size() << " channels";
    const std::span<const double> got = b.contact_weights()->data();
    ASSERT_EQ(got.size(), want.size());
    int differ = 0, density_differs = 0;
    const std::size_t c = static_cast<std::size_t>(density - channels.begin());
    for (std::size_t p = 0; p < got.size(); ++p) {
      differ += got[p] != want[p];
      density_differs += img[c * b.plane() + p] != static_cast<float>(want[p]);
    }
    EXPECT_EQ(differ, 0) << channels.size() << " channels";
    EXPECT_EQ(density_differs, 0) << channels.size() << " channels";
  }
}

/// The 40-circle seed scene (seed 5) of the builder-reuse tests: stepped 3 steps it is spread
/// over the box, 150 steps a pile low in it.
WorldDef forty_circles() {
  WorldDef wd;
  wd.bodies.count = 40;
  wd.bodies.seed = 5;
  return wd;
}

// The builder clears and converts only the grid rows its splats reach (the rows written by the
// previous call are cleared first): a builder used on another state before gives a fresh
// builder's image and contact weights bit for bit — a pile low in the box after bodies spread
// over it and back, for every kind of channel.
TEST(FeatureImage, AReusedBuilderGivesAFreshBuildersImageBitForBit) {
  const WorldDef wd = forty_circles();
  World early(wd), settled(wd);
  (void)test::step_then_assemble(early, 3, 50);
  (void)test::step_then_assemble(settled, 150, 50);
  ASSERT_GT(settled.contacts().size(), 10u);
  using C = FeatureChannel;
  const std::vector<std::vector<C>> sets = {
      {C::Mass, C::Vx, C::Vy, C::Omega, C::ContactDensity, C::LambdaPrevN, C::LambdaPrevT, C::VrelN, C::VrelT, C::Gap},
      {C::ContactDensity, C::Nx, C::Ny, C::Coverage, C::OrientC, C::OrientS},
      {C::Mass, C::ContactDensity, C::WPrevN, C::WPrevT}};
  for (const std::vector<C>& channels : sets) {
    FeatureImageDef def = FeatureImageDef::for_box(wd.world.width, wd.world.height);
    def.channels = channels;
    FeatureImageBuilder reused(def);
    for (const World* w : {&settled, &early, &settled, &settled}) {
      std::vector<float> got(reused.feature_size()), want(reused.feature_size());
      reused.features(w->bodies(), w->contacts(), w->previous_contacts(), &w->problem(), got);
      FeatureImageBuilder fresh(def);
      fresh.features(w->bodies(), w->contacts(), w->previous_contacts(), &w->problem(), want);
      EXPECT_EQ(std::memcmp(got.data(), want.data(), sizeof(float) * got.size()), 0)
          << channels.size() << " channels, " << w->contacts().size() << " contacts";
      ASSERT_NE(reused.contact_weights(), nullptr);
      const std::span<const double> a = reused.contact_weights()->data(), b = fresh.contact_weights()->data();
      EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * a.size()), 0) << channels.size() << " channels";
    }
  }
}

// The cnn starter hands the builder the key match it already has (one match per step) and
// hands the builder's nonzero rows to the inference plan (no scan of the image): with the
// match, the image is the builder's own bit for bit (a wrong match changes it: the match is
// read), and every channel is +0 (bit pattern 0) outside nonzero_rows().
TEST(FeatureImage, AGivenKeyMatchGivesTheSameImageAndNonzeroRowsBoundIt) {
  const WorldDef wd = forty_circles();
  World early(wd), settled(wd);
  (void)test::step_then_assemble(early, 3, 50);
  (void)test::step_then_assemble(settled, 150, 50);
  ASSERT_GT(settled.contacts().size(), 10u);
  using C = FeatureChannel;
  const std::vector<std::vector<C>> sets = {
      {C::Mass, C::Vx, C::Vy, C::Omega, C::ContactDensity, C::LambdaPrevN, C::LambdaPrevT, C::VrelN, C::VrelT, C::Gap},
      {C::Mass, C::ContactDensity, C::WPrevN, C::WPrevT}};
  for (const std::vector<C>& channels : sets) {
    FeatureImageDef def = FeatureImageDef::for_box(wd.world.width, wd.world.height);
    def.channels = channels;
    FeatureImageBuilder given(def), own(def);
    const int nx = given.nx(), ny = given.ny();
    for (const World* w : {&settled, &early, &settled}) {
      const std::vector<int> match = match_contacts_by_key(w->previous_contacts(), w->contacts());
      const bool persistent = std::any_of(match.begin(), match.end(), [](int m) { return m >= 0; });
      if (w == &settled) {
        ASSERT_TRUE(persistent);
      }
      std::vector<float> got(given.feature_size()), want(given.feature_size()), wrong(given.feature_size());
      given.features(w->bodies(), w->contacts(), w->previous_contacts(), &w->problem(), got, match);
      own.features(w->bodies(), w->contacts(), w->previous_contacts(), &w->problem(), want);
      EXPECT_EQ(std::memcmp(got.data(), want.data(), sizeof(float) * got.size()), 0) << channels.size() << " channels";
      const auto [lo, hi] = given.nonzero_rows();
      EXPECT_EQ(given.nonzero_rows(), own.nonzero_rows());
      EXPECT_TRUE(lo > 0 || hi < ny - 1) << "the pile leaves empty rows";
      int outside = 0;
      for (int c = 0; c < given.feature_channels(); ++c)
        for (int j = 0; j < ny; ++j)
          for (int i = 0; i < nx; ++i) {
            std::uint32_t b;
            const float v = at(got, c, j, i, ny, nx);
            std::memcpy(&b, &v, sizeof b);
            if ((j < lo || j > hi) && b != 0) ++outside;
          }
      EXPECT_EQ(outside, 0) << "nonzero values outside rows " << lo << ".." << hi;
      const std::vector<int> none(match.size(), -1);  // every contact new: λ_prev = 0
      FeatureImageBuilder other(def);
      other.features(w->bodies(), w->contacts(), w->previous_contacts(), &w->problem(), wrong, none);
      if (persistent) {
        EXPECT_NE(std::memcmp(got.data(), wrong.data(), sizeof(float) * got.size()), 0) << "the given match is read";
      }
    }
    std::vector<float> out(given.feature_size());
    const std::vector<int> short_match(settled.contacts().size() - 1, -1);
    EXPECT_THROW(given.features(settled.bodies(), settled.contacts(), settled.previous_contacts(), &settled.problem(), out,
                                short_match),
                 InvalidArgument);
  }
}

TEST(FeatureImage, ResidualLabelReadsBackAsLambdaStarMinusBuiltin) {
  WorldDef def;
  def.bodies.count = 40;
  def.bodies.seed = 5;
  World world(def);
  Eigen::VectorXd star;
  for (int s = 0; s < 250; ++s) {
    world.collide();
    star = solve_oracle(world.assemble()).lambda;
    if (s >= 200 && world.contacts().size() > 20) break;
    world.integrate(star);
  }
  ASSERT_GT(world.contacts().size(), 20u);
  FeatureImageDef img = FeatureImageDef::for_box(30, 30);
  img.channels = {FeatureChannel::LambdaPrevN, FeatureChannel::LambdaPrevT};
  FeatureImageBuilder b(img);
  const auto& cs = world.contacts();
  const std::vector<double> lam = world.constraints().gather(star);
  std::vector<float> feat(b.feature_size()), label(b.label_size());
  b.features(world.bodies(), cs, world.previous_contacts(), feat);
  b.labels(cs, lam, label);
  SphTransferDef t = b.def().sph;
  SphTransfer transfer(t);
  SphGrid g(t.grid);
  for (std::size_t k = 0; k < label.size(); ++k) g.data()[k] = double(label[k]) - double(feat[k]);
  std::vector<Vec2> pts;
  for (const Contact& c : cs) pts.push_back(c.point);
  const std::span<const double> back = transfer.gather(g, pts);
  const Eigen::VectorXd builtin = default_warm_starters().make("builtin")->initial_guess(StepView{world, nullptr});
  double scale = 1;
  for (double v : lam) scale = std::max(scale, std::abs(v));
  int changed = 0;
  for (int c = 0; c < static_cast<int>(cs.size()); ++c) {
    const double want = star[world.normal_row(c)] - builtin[world.normal_row(c)];
    changed += std::abs(want) > 1e-3 * scale;
    EXPECT_NEAR(back[2 * c], want, 1e-5 * scale) << "contact " << c;
  }
  EXPECT_GT(changed, 0);  // a non-trivial correction
}

// w_prev read back at the contacts is the LCP velocity A λ_prev + b of the builtin guess,
// computed here with the assembled A (the builder goes matrix-free through J); at contacts
// that builtin already solves it is ≈ 0, and no problem → a one-line error.
TEST(FeatureImage, WPrevReadsBackAsTheBuiltinGuessLcpVelocity) {
  WorldDef def;
  def.bodies.count = 40;
  def.bodies.seed = 5;
  World world(def);
  for (int s = 0; s < 250; ++s) {
    world.collide();
    const Eigen::VectorXd star = solve_oracle(world.assemble()).lambda;
    if (s >= 200 && world.contacts().size() > 20) break;
    world.integrate(star);
  }
  ASSERT_GT(world.contacts().size(), 20u);
  FeatureImageDef img = FeatureImageDef::for_box(30, 30);
  img.channels = {FeatureChannel::Mass, FeatureChannel::WPrevN, FeatureChannel::WPrevT};
  ASSERT_TRUE(needs_lcp_problem(img.channels));
  FeatureImageBuilder b(img);
  const auto& cs = world.contacts();
  std::vector<float> feat(b.feature_size());
  EXPECT_THROW(b.features(world.bodies(), cs, world.previous_contacts(), feat), InvalidArgument);
  b.features(world.bodies(), cs, world.previous_contacts(), &world.problem(), feat);

  LcpProblem p = world.problem();
  p.ensure_assembled_matrix();
  Eigen::VectorXd prev = Eigen::VectorXd::Zero(p.rows());
  const std::vector<int> match = match_contacts_by_key(world.previous_contacts(), cs);
  int persisting = 0;
  for (std::size_t c = 0; c < cs.size(); ++c) {
    if (match[c] < 0) continue;
    ++persisting;
    const Contact& q = world.previous_contacts()[static_cast<std::size_t>(match[c])];
    world.constraints().put(static_cast<int>(c), q.lambda_n, q.lambda_t, prev);
  }
  ASSERT_GT(persisting, 10);
  const Eigen::VectorXd w = p.A * prev + p.b;

  SphTransferDef t = b.def().sph;
  t.grid.channels = 2;
  SphTransfer transfer(t);
  SphGrid g(t.grid);
  const std::size_t P = b.plane();
  std::copy(feat.begin() + P, feat.end(), g.data().begin());  // channels 1, 2 of the image
  std::vector<Vec2> pts;
  for (const Contact& c : cs) pts.push_back(c.point);
  const std::span<const double> back = transfer.gather(g, pts);
  double scale = 1e-3;
  for (int i = 0; i < p.rows(); ++i) scale = std::max(scale, std::abs(w[i]));
  int moving = 0;
  for (int c = 0; c < static_cast<int>(cs.size()); ++c) {
    const double wn = world.constraints().lambda_n(w, c), wt = world.constraints().lambda_t(w, c);
    moving += std::abs(wn) > 1e-3 * scale;
    EXPECT_NEAR(back[2 * c], wn, 1e-5 * scale) << "contact " << c;
    EXPECT_NEAR(back[2 * c + 1], wt, 1e-5 * scale) << "contact " << c;
  }
  EXPECT_GT(moving, 0);  // builtin is not exact on this step: the channel carries something
}

TEST(FeatureImage, LabelsAreShepardNumeratorsOrientedLikeTheFeatures) {
  FeatureImageBuilder b(FeatureImageDef::for_box(30, 30));
  const double d = b.def().sph.grid.spacing;
  Contact c;
  c.point = {11.2, 25.7};
  std::vector<Contact> cs{c};
  const std::vector<double> lambda{40.0, -12.0};
  std::vector<float> img(b.label_size());
  b.labels(cs, lambda, img);
  const int ny = b.ny(), nx = b.nx();
  const auto [j, i] = argmax(img, 0, ny, nx);
  EXPECT_EQ(j, static_cast<int>(std::lround(25.7 / d)));
  EXPECT_EQ(i, static_cast<int>(std::lround(11.2 / d)));
  const SphKernel W(b.def().sph.kernel, b.def().sph.support);
  const double w = W(std::hypot(i * d - 11.2, j * d - 25.7));
  EXPECT_NEAR(at(img, 0, j, i, ny, nx), w * 40.0, 1e-5 * w * 40);
  EXPECT_NEAR(at(img, 1, j, i, ny, nx), w * -12.0, 1e-5 * w * 12);
}

TEST(FeatureImage, BadChannelListsAndSizesAreErrors) {
  EXPECT_THROW(parse_feature_channels("mass,speed"), ConfigError);
  EXPECT_THROW(parse_feature_channels("mass,mass"), ConfigError);
  EXPECT_THROW(parse_feature_channels(""), ConfigError);
  EXPECT_EQ(parse_feature_channels("nx, ny").size(), 2u);
  FeatureImageDef def = FeatureImageDef::for_box(30, 30);
  def.channels.clear();
  EXPECT_THROW(FeatureImageBuilder{def}, ConfigError);
  FeatureImageBuilder b(FeatureImageDef::for_box(30, 30));
  std::vector<float> small(10);
  BodyState s;
  EXPECT_THROW(b.features(s, {}, small), InvalidArgument);
  EXPECT_THROW(b.labels({}, std::vector<double>{1.0}, small), InvalidArgument);
}

// The default grid is a valid one: the data set's default feature image (61 x 61 on the
// seed's box, default channels, poly6), absolute labels named lambda_n, lambda_t.
TEST(ModelGrid, DefaultIsTheDataSetsDefaultImage) {
  const ModelGrid g;
  EXPECT_NO_THROW(g.image.validate());
  const FeatureImageBuilder b(g.image);
  EXPECT_EQ(g.nx(), b.nx());
  EXPECT_EQ(g.ny(), b.ny());
  EXPECT_EQ(g.nx(), 61);
  EXPECT_EQ(g.image.channels, default_feature_channels());
  EXPECT_EQ(g.image.sph.kernel, FeatureImageDef::for_box(30, 30).sph.kernel);
  EXPECT_EQ(g.label_channels, label_channel_names());
  EXPECT_EQ(g.labels, LabelDef{});
  const Model m(default_arch(), g, b.feature_channels());
  EXPECT_EQ(m.grid().nx(), 61);
  // The channel count must match the network's input.
  EXPECT_THROW(Model(default_arch(), g, b.feature_channels() + 1), InvalidArgument);
}

}  // namespace
}  // namespace dc
