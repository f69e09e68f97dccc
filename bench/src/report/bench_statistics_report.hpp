#pragma once
// The bench statistics (bench_statistics.hpp) in the report: a Markdown section for
// report.md, a JSON object for summary.json ("statistics") and the /statistics group of
// results.h5. Layouts: docs/bench.md "Uncertainty".
#include <string>

#include "dc/bench/bench_statistics.hpp"

namespace dc {
class H5File;
class JsonWriter;
}

namespace dc::bench {

/// report.md's "Uncertainty" section: per-starter intervals and per-seed medians, the ratios
/// to zero and builtin with a distinguishable / not distinguishable verdict (a sweep count
/// above the run's sweeps is printed as "never").
std::string statistics_markdown(const BenchStatistics& s);

/// Writes the "statistics" object of summary.json as the next value of `j` (numbers; a
/// never-converged value is sweeps + 1).
void statistics_json(JsonWriter& j, const BenchStatistics& s);

/// Writes /statistics into an open results.h5.
void write_statistics_h5(H5File& f, const BenchStatistics& s);

/// One sentence per reference listing the starters whose median-sweeps ratio interval
/// contains 1 ("" if every pair is distinguishable).
std::string indistinguishable_summary(const BenchStatistics& s);

}  // namespace dc::bench
