// The shipped model (models/default.h5) on the seed scene: the starter's fused inference
// plan gives the unfused network's output (Model::network_output_at: standardise a copy,
// Network::forward_at) bit for bit, at every node of the grid and at the contacts' stencil
// nodes, over consecutive steps (buffers reused across calls); the whole warm start (one key
// match per step, the builder's nonzero rows handed to the plan, the stencils shared by the
// network's pixels and the read-back) equals its parts taken one by one on the unfused path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "dc/cnn/cnn_warm_starter.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "dc/learning/labels.hpp"
#include "dc/sph/sph_grid.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {
namespace {

/// The grid nodes of the bilinear stencils of the world's contacts, each once.
std::vector<int> stencil_nodes(const FeatureImageDef& def, const World& world) {
  SphGrid g(SphGridDef{def.sph.grid.width, def.sph.grid.height, def.sph.grid.spacing, 1});
  std::vector<char> seen(static_cast<std::size_t>(g.nx() * g.ny()), 0);
  std::vector<int> nodes;
  for (const Contact& c : world.contacts()) {
    const BilinearStencil st = g.stencil(c.point);
    for (const int j : {st.j0, st.j1})
      for (const int i : {st.i0, st.i1})
        if (!seen[static_cast<std::size_t>(j * g.nx() + i)]++) nodes.push_back(j * g.nx() + i);
  }
  return nodes;
}

TEST(ShippedModelInference, FusedPlanEqualsTheUnfusedNetworkBitForBit) {
  const auto cnn = CnnWarmStarter::load(std::string(DC_SOURCE_DIR) + "/models/default.h5", "cnn", false);
  World world(default_world_def());
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 100;
  o.record_theta = false;
  const auto zero = [](const World& w) { return Eigen::VectorXd::Zero(w.problem().rows()).eval(); };
  for (int k = 0; k < 120; ++k) world.step(*solver, o, zero);
  FeatureImageDef def = cnn->model().grid().image;
  def.sph.grid.width = world.def().world.width;
  def.sph.grid.height = world.def().world.height;
  FeatureImageBuilder builder(def);
  Tensor features(1, builder.feature_channels(), builder.ny(), builder.nx());
  const int P = builder.nx() * builder.ny();
  std::vector<int> every(static_cast<std::size_t>(P));
  for (int p = 0; p < P; ++p) every[static_cast<std::size_t>(p)] = p;
  for (int step = 0; step < 3; ++step) {
    world.collide();
    world.assemble();
    ASSERT_GT(world.contacts().size(), 50u) << "the seed pile has settled into contact";
    builder.features(world.bodies(), world.contacts(), world.previous_contacts(),
                     std::span<float>(features.data(), features.size()));
    for (const std::vector<int>& pixels : {stencil_nodes(def, world), every}) {
      const Tensor want = cnn->model().network_output_at(features, pixels);
      InferencePlan& plan = cnn->inference_plan(world);
#if defined(__AVX512F__)
      EXPECT_TRUE(plan.fused());
#endif
      const Tensor& got = plan.run(features, pixels);
      ASSERT_EQ(got.shape(), want.shape());
      int differ = 0;
      for (int c = 0; c < got.c(); ++c)
        for (const int p : pixels) {
          const std::size_t i = static_cast<std::size_t>(c * P + p);
          differ += got[i] != want[i];
        }
      EXPECT_EQ(differ, 0) << "step " << step << ", " << pixels.size() << " pixels";
    }
    world.step(*solver, o, zero);
  }
}

/// The starter's force caps (cnn_warm_starter.cpp): W + max(0, −b_i)/A_ii per row, with
/// A_ii = Δt Σ_j J_ij² M⁻¹_jj — the same operations in the same order.
Eigen::VectorXd starter_caps(const World& w) {
  double weight = 0;
  for (const double m : w.bodies().mass) weight += m;
  weight *= length(w.def().world.gravity);
  const LcpProblem& p = w.problem();
  Eigen::VectorXd cap = Eigen::VectorXd::Constant(p.rows(), weight);
  for (int i = 0; i < p.rows(); ++i) {
    double aii = 0;
    if (p.has_jacobian()) {
      for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) aii += it.value() * it.value() * p.inv_mass[it.col()];
      aii *= p.dt;
    } else {
      aii = p.A.coeff(i, i);
    }
    if (aii > 0 && p.b[i] < 0) cap[i] += -p.b[i] / aii;
  }
  return cap;
}

TEST(ShippedModelInference, TheWarmStartEqualsItsPartsOnTheUnfusedPathBitForBit) {
  const std::string path = std::string(DC_SOURCE_DIR) + "/models/default.h5";
  const auto cnn = CnnWarmStarter::load(path, "cnn", false);
  const auto parts = CnnWarmStarter::load(path, "cnn", false);  // the reference's read-back
  ASSERT_EQ(cnn->model().grid().labels.kind, LabelKind::Residual);
  World world(default_world_def());
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 100;
  o.record_theta = false;
  const auto builtin = [](const World& w) {
    Eigen::VectorXd l = Eigen::VectorXd::Zero(w.problem().rows());
    const auto match = match_contacts_by_key(w.previous_contacts(), w.contacts());
    for (std::size_t c = 0; c < match.size(); ++c)
      if (match[c] >= 0) {
        const Contact& p = w.previous_contacts()[static_cast<std::size_t>(match[c])];
        w.constraints().put(static_cast<int>(c), p.lambda_n, p.lambda_t, l);
      }
    return l;
  };
  for (int k = 0; k < 110; ++k) world.step(*solver, o, builtin);
  FeatureImageDef def = cnn->model().grid().image;
  def.sph.grid.width = world.def().world.width;
  def.sph.grid.height = world.def().world.height;
  FeatureImageBuilder builder(def);
  Tensor features(1, builder.feature_channels(), builder.ny(), builder.nx());
  for (int step = 0; step < 4; ++step) {
    world.collide();
    world.assemble();
    ASSERT_GT(world.contacts().size(), 50u) << "the seed pile has settled into contact";
    const Eigen::VectorXd got = cnn->initial_guess(StepView{world});
    // The parts: features (the builder's own key match), the unfused network at the stencil
    // nodes, the read-back with S splatted again and the stencils recomputed, then the
    // residual composition of initial_guess.
    builder.features(world.bodies(), world.contacts(), world.previous_contacts(), &world.problem(),
                     std::span<float>(features.data(), features.size()));
    const Tensor y = parts->model().network_output_at(features, stencil_nodes(def, world));
    Eigen::VectorXd want = parts->guess_from_output(world, y, false);
    const Eigen::VectorXd cap = starter_caps(world);
    for (Eigen::Index i = 0; i < want.size(); ++i) want[i] = std::isnan(want[i]) ? 0.0 : std::clamp(want[i], -cap[i], cap[i]);
    apply_deadzone(std::span<double>(want.data(), static_cast<std::size_t>(want.size())),
                   parts->model().grid().labels.deadzone);
    const auto match = match_contacts_by_key(world.previous_contacts(), world.contacts());
    for (std::size_t c = 0; c < match.size(); ++c) {
      if (match[c] < 0) continue;
      const Contact& p = world.previous_contacts()[static_cast<std::size_t>(match[c])];
      const ContactConstraints& cons = world.constraints();
      const int k = static_cast<int>(c);
      cons.put(k, cons.lambda_n(want, k) + p.lambda_n, cons.lambda_t(want, k) + p.lambda_t, want);
    }
    project_feasible(world.problem(), want);
    ASSERT_EQ(got.size(), want.size());
    int differ = 0;
    for (Eigen::Index i = 0; i < got.size(); ++i) differ += std::memcmp(&got[i], &want[i], sizeof(double)) != 0;
    EXPECT_EQ(differ, 0) << "step " << step << ", " << got.size() << " rows";
    EXPECT_GT((got - builtin(world)).cwiseAbs().maxCoeff(), 0.0) << "the network corrects builtin";
    world.step(*solver, o, builtin);
  }
}

}  // namespace
}  // namespace dc
