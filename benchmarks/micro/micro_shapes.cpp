// Google Benchmark of the narrow phase per pair (docs/design.md §8.1): libccd's GJK+EPA (0) and
// MPR (1) against the engine's analytic paths, on overlapping or speculative (gap > 0) pairs:
//   BM_CircleCircleAnalytic, BM_CirclePolygonAnalytic (Box2D-style Voronoi test),
//   BM_CirclePolygonCcd/{0,1}, BM_BoxBoxSat (SAT + two-point clipping, the engine's path),
//   BM_BoxBoxCcd/{0,1} (libccd normal + the same clipping, polygon_sat = false),
//   BM_BoxBoxCcdOnly/{0,1} (normal and depth only), BM_EllipseEllipseCcd/{0,1} (libccd only: no
//   analytic test), BM_BoxWallAnalytic (polygon–plane).
// Each pair cycles through 64 poses (random angles, distances over overlap and speculative gap)
// so branch prediction does not see one pose only.
//   cmake --build build --target micro_shapes && build/bin/micro_shapes
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "collision/narrow_phase.hpp"
#include "dc/engine/shape_collide.hpp"
#include "dc/engine/shape_narrow_phase.hpp"

namespace {

using dc::BodyState;
using dc::CcdMethod;
using dc::ContactPoint;
using dc::ShapePose;
using dc::Vec2;

constexpr int kPoses = 64;

/// Two bodies per pose: body 2i at the origin, body 2i+1 at distance d in a random direction.
struct Pairs {
  BodyState s;
  std::vector<std::vector<Vec2>> wv, wn;
  std::vector<ShapePose> poses;
};

Pairs make_pairs(const dc::ShapeDef& a, const dc::ShapeDef& b, double reach) {
  Pairs p;
  unsigned x = 12345;
  auto rnd = [&] {
    x = x * 1664525u + 1013904223u;
    return (x >> 8) / 16777216.0;
  };
  for (int i = 0; i < kPoses; ++i) {
    const double phi = 2 * M_PI * rnd();
    // centre distance across [0.8, 1.0 + margin] of the sum of the "typical" radii
    const double d = (0.8 + 0.25 * rnd()) * reach;
    p.s.add_shaped(a, dc::Motion::Dynamic, {0, 0}, 1.0, {}, 2 * M_PI * rnd());
    p.s.add_shaped(b, dc::Motion::Dynamic, {d * std::cos(phi), d * std::sin(phi)}, 1.0, {}, 2 * M_PI * rnd());
  }
  p.wv.resize(p.s.size());
  p.wn.resize(p.s.size());
  for (std::size_t k = 0; k < p.s.size(); ++k)
    p.poses.push_back(dc::make_pose(p.s, static_cast<int>(k), p.wv[k], p.wn[k]));
  return p;
}

const dc::ShapeDef kBox = dc::make_box({1.0, 1.0}, "box");
const dc::ShapeDef kEllipse = dc::make_ellipse({0.8, 0.4}, "ellipse");
const dc::ShapeDef kCircle = dc::make_circle(0.5);
constexpr double kInflate = 0.02;  // the default speculative reach of a resting body (margin/2 + ...)

void run_pairs(benchmark::State& st, const Pairs& p, bool manifold, CcdMethod m, bool polygon_sat = false) {
  int i = 0, hits = 0;
  ContactPoint pts[2];
  for (auto _ : st) {
    const ShapePose& a = p.poses[static_cast<std::size_t>(2 * i)];
    const ShapePose& b = p.poses[static_cast<std::size_t>(2 * i + 1)];
    if (manifold) {
      hits += dc::collide_shapes(a, b, kInflate, kInflate, pts, m, polygon_sat);
    } else {
      Vec2 n;
      double gap;
      hits += dc::ccd_normal_gap(a, b, kInflate, kInflate, m, n, gap) ? 1 : 0;
    }
    benchmark::DoNotOptimize(pts);
    i = (i + 1) % kPoses;
  }
  st.counters["points_per_pair"] = static_cast<double>(hits) / static_cast<double>(st.iterations());
}

void BM_CircleCircleAnalytic(benchmark::State& st) {
  Pairs p = make_pairs(kCircle, kCircle, 1.0);
  int i = 0, hits = 0;
  for (auto _ : st) {
    auto c = dc::circle_circle(p.s, 2 * i, 2 * i + 1, 2 * kInflate);
    hits += c ? 1 : 0;
    benchmark::DoNotOptimize(c);
    i = (i + 1) % kPoses;
  }
  st.counters["points_per_pair"] = static_cast<double>(hits) / static_cast<double>(st.iterations());
}
BENCHMARK(BM_CircleCircleAnalytic);

void BM_CirclePolygonAnalytic(benchmark::State& st) {
  Pairs p = make_pairs(kCircle, kBox, 1.05);
  int i = 0, hits = 0;
  ContactPoint pts[1];
  for (auto _ : st) {
    hits += dc::collide_circle_polygon(p.poses[static_cast<std::size_t>(2 * i)],
                                       p.poses[static_cast<std::size_t>(2 * i + 1)], 2 * kInflate, true, pts);
    benchmark::DoNotOptimize(pts);
    i = (i + 1) % kPoses;
  }
  st.counters["points_per_pair"] = static_cast<double>(hits) / static_cast<double>(st.iterations());
}
BENCHMARK(BM_CirclePolygonAnalytic);

void BM_CirclePolygonCcd(benchmark::State& st) {
  run_pairs(st, make_pairs(kCircle, kBox, 1.05), false, static_cast<CcdMethod>(st.range(0)));
}
BENCHMARK(BM_CirclePolygonCcd)->Arg(0)->Arg(1);

void BM_BoxBoxCcd(benchmark::State& st) {
  run_pairs(st, make_pairs(kBox, kBox, 1.2), true, static_cast<CcdMethod>(st.range(0)));
}
BENCHMARK(BM_BoxBoxCcd)->Arg(0)->Arg(1);

void BM_BoxBoxSat(benchmark::State& st) {
  run_pairs(st, make_pairs(kBox, kBox, 1.2), true, CcdMethod::GjkEpa, true);
}
BENCHMARK(BM_BoxBoxSat);

void BM_BoxBoxCcdOnly(benchmark::State& st) {
  run_pairs(st, make_pairs(kBox, kBox, 1.2), false, static_cast<CcdMethod>(st.range(0)));
}
BENCHMARK(BM_BoxBoxCcdOnly)->Arg(0)->Arg(1);

void BM_EllipseEllipseCcd(benchmark::State& st) {
  run_pairs(st, make_pairs(kEllipse, kEllipse, 1.2), true, static_cast<CcdMethod>(st.range(0)));
}
BENCHMARK(BM_EllipseEllipseCcd)->Arg(0)->Arg(1);

void BM_BoxWallAnalytic(benchmark::State& st) {
  Pairs p = make_pairs(kBox, kBox, 1.2);
  int i = 0, hits = 0;
  ContactPoint pts[2];
  for (auto _ : st) {
    const ShapePose& b = p.poses[static_cast<std::size_t>(2 * i + 1)];
    hits += dc::collide_shape_plane(b, {0, 1}, b.x.y - 0.6, 2 * kInflate, pts);
    benchmark::DoNotOptimize(pts);
    i = (i + 1) % kPoses;
  }
  st.counters["points_per_pair"] = static_cast<double>(hits) / static_cast<double>(st.iterations());
}
BENCHMARK(BM_BoxWallAnalytic);

}  // namespace

BENCHMARK_MAIN();
