#include "dc/bench/quantiles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "dc/core/error.hpp"

namespace dc::bench {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

double quantile_sorted(const std::vector<double>& v, double p) {
  const double pos = p * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  const double t = pos - static_cast<double>(lo);
  if (std::isinf(v[lo]) || std::isinf(v[hi])) return t < 0.5 ? v[lo] : v[hi];
  return v[lo] + t * (v[hi] - v[lo]);
}

double quantile(std::vector<double> values, double p) {
  if (!(p >= 0.0 && p <= 1.0)) throw InvalidArgument("quantile: p must lie in [0, 1], got " + std::to_string(p));
  if (std::any_of(values.begin(), values.end(), [](double x) { return std::isnan(x); }))
    throw InvalidArgument("quantile: a value is NaN");
  if (values.empty()) return kNaN;
  std::sort(values.begin(), values.end());
  return quantile_sorted(values, p);
}

Quartiles quartiles(std::vector<double> v) {
  Quartiles q;
  if (v.empty()) {
    q.q1 = q.median = q.q3 = kNaN;
    return q;
  }
  std::sort(v.begin(), v.end());
  auto at = [&](double f) { return quantile_sorted(v, f); };
  q.q1 = at(0.25);
  q.median = at(0.5);
  q.q3 = at(0.75);
  return q;
}

double median_of(std::vector<double> v) {
  if (v.empty()) return kNaN;
  const std::size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h), v.end());
  const double upper = v[h];
  if (v.size() % 2 == 1) return upper;
  const double lower = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h));
  return 0.5 * (lower + upper);
}

double mean_of(const std::vector<double>& v) {
  if (v.empty()) return kNaN;
  return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

}  // namespace dc::bench
