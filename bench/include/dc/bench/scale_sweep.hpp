#pragma once
// The size sweep (`deepcontact bench --scale N1,N2,…`, docs/bench.md "Size sweep"): one bench
// run per body count N on the scene scaled to N bodies keeping its shape, and a table /
// plot of every starter's sweeps to tol, residual at the budget, sweeps with the higher cap
// and total time against N.
#include <string>
#include <vector>

#include "dc/bench/bench_runner.hpp"
#include "dc/bench/bench_summary.hpp"

namespace dc::bench {

/// How a scene grows with N.
enum class ScaleAxis {
  Both,    ///< keep the aspect ratio and the filling density: both box sides × √(N/N₀)
  Height,  ///< keep the width: the height × N/N₀ (a deeper pile of the same width)
};

/// Bodies a scene puts into the world over a run: [bodies] count + every [[body]] + the
/// inflow's emissions (N₀ of the scaling).
int scene_body_count(const WorldDef& def);

/// `def` scaled to about `n` bodies: [bodies] count and [inflow] rate × n/N₀ (rounded),
/// the box, Gaussian mean/sigma, regions and explicit body positions stretched by the axis
/// factors (radii unchanged, so the filling density stays). ConfigError for n < 1 or a scene
/// without bodies.
WorldDef scale_scene(const WorldDef& def, int n, ScaleAxis axis);

struct ScalePoint {
  int n = 0;                 ///< requested body count
  int bodies = 0;            ///< bodies of the scaled scene (scene_body_count)
  double width = 0, height = 0;
  BenchResults results;
  std::vector<StarterSummary> summary;
};

/// Runs `base` at each count (the oracle skipped from `no_oracle_from` bodies on; 0 = never).
std::vector<ScalePoint> run_scale_sweep(const BenchOptions& base, const std::vector<int>& counts, ScaleAxis axis,
                                        int no_oracle_from, const WarmStarterRegistry& registry,
                                        const ProgressFn& progress = {});

/// Plain-text (or Markdown) table: one row per (N, starter).
std::string format_scale_table(const std::vector<ScalePoint>& points, bool markdown);

/// Writes scale.md, scale.json, scale.csv and scale.png (bench/plots/scale_plot.py) into dir.
std::vector<std::string> write_scale_report(const std::vector<ScalePoint>& points, ScaleAxis axis,
                                            const std::string& dir);

}  // namespace dc::bench
