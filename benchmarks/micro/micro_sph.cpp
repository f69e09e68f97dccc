// Micro-benchmarks of the SPH particle ↔ grid transfer (warmstart/sph_*.hpp) at the seed
// settings: ~400 contact points × 2 channels (λ_n, λ_t) splatted onto the 61 × 61 grid
// (poly6, d = h = 0.5) and the 121 × 121 grid (spiky, d = h = 0.25), plus the read-backs.
// The points are clustered like the seed scene's contacts (a Gaussian pile in the lower
// half of the 30 × 30 box) rather than uniform, so neighbour boxes overlap as in practice.
// Reported time is per call (one splat of all points = one step of the sph warm starter).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

#include "dc/core/rng.hpp"
#include "dc/sph/sph_transfer.hpp"

namespace {

using namespace dc;

struct Points {
  std::vector<Vec2> p;
  std::vector<double> v;  // particle-major, 2 channels
};

Points contact_like_points(int n) {
  Rng rng(42);
  Points out;
  for (int k = 0; k < n; ++k) {
    const double x = std::clamp(15.0 + rng.gaussian(4.65), 0.0, 30.0);
    const double y = std::clamp(4.0 + std::abs(rng.gaussian(4.0)), 0.0, 30.0);
    out.p.push_back({x, y});
    out.v.push_back(rng.uniform(0.0, 20.0));   // λ_n [N]
    out.v.push_back(rng.uniform(-5.0, 5.0));   // λ_t [N]
  }
  return out;
}

SphTransferDef seed_def(SphKernelType kernel, double d, SphNormalisation mode) {
  SphTransferDef def;
  def.grid = SphGridDef{30.0, 30.0, d, 2};
  def.kernel = kernel;
  def.support = d;
  def.normalisation = mode;
  return def;
}

// Args: 0 = poly6 d = h = 0.5 (61 × 61), 1 = spiky d = h = 0.25 (121 × 121); points.
SphTransferDef def_of(const benchmark::State& state, SphNormalisation mode) {
  return state.range(0) == 0 ? seed_def(SphKernelType::Poly6, 0.5, mode)
                             : seed_def(SphKernelType::Spiky, 0.25, mode);
}

void BM_SphSplat(benchmark::State& state) {
  SphTransfer t(def_of(state, SphNormalisation::None));
  const Points pts = contact_like_points(static_cast<int>(state.range(1)));
  for (auto _ : state) {
    const SphGrid& g = t.splat(pts.p, pts.v);
    benchmark::DoNotOptimize(g.data().data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(state.range(0) == 0 ? "poly6 61x61 (+S)" : "spiky 121x121 (+S)");
  state.counters["points"] = static_cast<double>(pts.p.size());
  state.counters["nodes_in_support/pt"] =
      static_cast<double>(t.last_splat().nodes_in_support) / pts.p.size();
}

void BM_SphGatherBilinear(benchmark::State& state) {
  SphTransfer t(def_of(state, SphNormalisation::None));
  const Points pts = contact_like_points(static_cast<int>(state.range(1)));
  t.splat(pts.p, pts.v);
  for (auto _ : state) {
    const auto out = t.gather(t.grid(), pts.p);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetLabel(state.range(0) == 0 ? "61x61" : "121x121");
}

void BM_SphRoundTripShepard(benchmark::State& state) {
  SphTransfer t(def_of(state, SphNormalisation::Shepard));
  const Points pts = contact_like_points(static_cast<int>(state.range(1)));
  for (auto _ : state) {
    const auto out = t.round_trip(pts.p, pts.v);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetLabel(state.range(0) == 0 ? "poly6 61x61" : "spiky 121x121");
}

void BM_SphRoundTripLegacy(benchmark::State& state) {
  SphTransfer t(def_of(state, SphNormalisation::SumToOneLegacy));
  const Points pts = contact_like_points(static_cast<int>(state.range(1)));
  for (auto _ : state) {
    const auto out = t.round_trip(pts.p, pts.v);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetLabel(state.range(0) == 0 ? "poly6 61x61" : "spiky 121x121");
}

BENCHMARK(BM_SphSplat)->Args({0, 400})->Args({1, 400})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SphGatherBilinear)->Args({0, 400})->Args({1, 400})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SphRoundTripShepard)->Args({0, 400})->Args({1, 400})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SphRoundTripLegacy)->Args({0, 400})->Args({1, 400})->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
