#pragma once
// Test helper of the learning suite: the parameters of a small, fast data set (a pile in a
// box × box world, its default feature image on that box).
#include "dc/cnn/data_set.hpp"

namespace dc::test {

/// `steps` steps per simulation in a box × box world: bodies around the centre (σ = box/6),
/// the default feature image on the box, scene seed `seed`, counts count_min..count_max.
inline DataSetParams small_data_set_params(double box, int steps, std::uint64_t seed, int count_min, int count_max) {
  DataSetParams p;
  p.scene.world.width = box;
  p.scene.world.height = box;
  p.scene.bodies.mean = {box / 2, box / 2};
  p.scene.bodies.sigma = box / 6;
  p.scene.time.steps = steps;
  p.image = FeatureImageDef::for_box(box, box);
  p.seed = seed;
  p.count_min = count_min;
  p.count_max = count_max;
  return p;
}

}  // namespace dc::test
