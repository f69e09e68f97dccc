// The shipped model (models/default.h5) on the seed scene: the starter's fused inference
// plan gives the unfused network's output (Model::network_output_at: standardise a copy,
// Network::forward_at) bit for bit, at every node of the grid and at the contacts' stencil
// nodes, over consecutive steps (buffers reused across calls).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dc/cnn/cnn_warm_starter.hpp"
#include "dc/engine/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "dc/sph/sph_grid.hpp"

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

}  // namespace
}  // namespace dc
