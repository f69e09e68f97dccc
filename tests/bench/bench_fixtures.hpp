#pragma once
// Small bench runs shared by the bench tests and the research tests of the bench with oracles.
#include <stdexcept>
#include <string>
#include <vector>

#include "dc/bench/bench_runner.hpp"
#include "dc/bench/bench_summary.hpp"

namespace dc::test {

/// 24 discs settling on the floor, 160 steps, 600 sweeps, seed 3; zero, builtin, copy, sph, sph-prev.
inline bench::BenchOptions small_pile() {
  bench::BenchOptions o;
  o.scene.bodies.count = 24;
  o.scene.bodies.mean = {15.0, 5.0};
  o.scene.bodies.sigma = 3.0;
  o.scene.time.steps = 160;
  o.sweeps = 600;
  o.seeds = {3};
  o.warmstarts = {"zero", "builtin", "copy", "sph", "sph-prev"};
  return o;
}

/// 30 discs, 120 steps, a low cap of 60 sweeps (many steps miss tol) raised to 2000 for the
/// unconverged ones, seed 2; zero and builtin's variants.
inline bench::BenchOptions capped_pile() {
  bench::BenchOptions o;
  o.scene.bodies.count = 30;
  o.scene.bodies.mean = {15.0, 5.0};
  o.scene.bodies.sigma = 3.0;
  o.scene.time.steps = 120;
  o.sweeps = 60;  // low: many steps miss tol within it
  o.max_sweeps = 2000;
  o.seeds = {2};
  o.warmstarts = {"zero", "builtin", "builtin-extrapolate", "builtin-statics"};
  return o;
}

/// The summary of starter `n` (std::runtime_error when the run has none).
inline const bench::StarterSummary& get(const std::vector<bench::StarterSummary>& s, const std::string& n) {
  for (const auto& x : s)
    if (x.name == n) return x;
  throw std::runtime_error("no starter " + n);
}

}  // namespace dc::test
