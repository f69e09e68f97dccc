#pragma once
// Order statistics of one sample (and its mean): the one definition of the bench's quantiles,
// used by the table and summary.json (quartiles), the bootstrap (quantile_sorted, median_of,
// mean_of) and by studies that report a distribution the way the bench does (quantile).
//
// Two medians, on purpose: quartiles(v).median interpolates at position ½(n − 1), i.e.
// lo + ½(hi − lo) for an even count, while median_of returns ½(lo + hi). The two can differ
// in the last bit (and differ next to an infinite value); the table and summary.json were
// defined with the first, the bootstrap with the second, so each keeps its own and the
// reports stay bit-identical.
#include <vector>

namespace dc::bench {

/// The p-quantile (0 ≤ p ≤ 1) of sorted, non-empty `v` by linear interpolation between order
/// statistics at position p·(n − 1); next to an infinite value, the nearer order statistic.
double quantile_sorted(const std::vector<double>& v, double p);

/// The p-quantile of `values` in any order: quantile_sorted of a sorted copy, NaN if empty.
/// InvalidArgument when p is outside [0, 1] or a value is NaN (NaN has no order).
double quantile(std::vector<double> values, double p);

struct Quartiles { double q1 = 0, median = 0, q3 = 0; };
/// Quartiles by linear interpolation (quantile_sorted at ¼, ½, ¾); empty input gives NaNs.
Quartiles quartiles(std::vector<double> values);

/// Median (mean of the two middle values for an even count) and mean; NaN if empty.
double median_of(std::vector<double> v);
double mean_of(const std::vector<double>& v);

}  // namespace dc::bench
