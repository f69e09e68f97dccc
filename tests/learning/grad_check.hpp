#pragma once
// Central-difference gradient checking shared by the dc_learning tests.
//
// For a scalar objective L(θ) evaluated in double from float activations, the numeric
// derivative is (L(θ + ε e_i) − L(θ − ε e_i)) / 2ε. It is compared with the analytic one by
// the symmetric relative error  |a − n| / (|a| + |n| + floor), where floor = 1e-2 · rms(a)
// keeps near-zero entries from dividing by rounding noise.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dc/core/rng.hpp"
#include "dc/learning/tensor.hpp"

namespace dc::test {

struct GradCheckStats {
  double max_err = 0.0;
  int checked = 0;
  int bad = 0;  ///< entries with error above tolerance (e.g. a ReLU kink crossed)
};

inline void fill_gaussian(Tensor& t, Rng& rng, double sigma = 1.0, double min_abs = 0.0) {
  for (std::size_t i = 0; i < t.size(); ++i) {
    double v = rng.gaussian(sigma);
    if (std::abs(v) < min_abs) v = v < 0 ? v - min_abs : v + min_abs;
    t[i] = static_cast<float>(v);
  }
}

/// Check `analytic` (dL/dt) against central differences of `loss` w.r.t. the entries of
/// `t`, at up to `max_checks` entries chosen with rng (all when t is small). Up to
/// `max_bad` entries may exceed `tol` (for functions with ReLU kinks, where a step can
/// cross a kink and the central difference is then simply not the derivative).
inline GradCheckStats check_gradient(const std::string& what, Tensor& t, const Tensor& analytic,
                                     const std::function<double()>& loss, double eps, double tol,
                                     Rng& rng, int max_checks = 60, int max_bad = 0) {
  EXPECT_EQ(t.shape(), analytic.shape()) << what;
  double ss = 0.0;
  for (std::size_t i = 0; i < analytic.size(); ++i) ss += double(analytic[i]) * analytic[i];
  const double floor = 1e-2 * std::sqrt(ss / std::max<std::size_t>(1, analytic.size())) + 1e-12;
  std::vector<std::size_t> idx;
  if (static_cast<int>(t.size()) <= max_checks) {
    for (std::size_t i = 0; i < t.size(); ++i) idx.push_back(i);
  } else {
    for (int k = 0; k < max_checks; ++k) idx.push_back(rng.uniform_int(t.size()));
  }
  GradCheckStats st;
  for (std::size_t i : idx) {
    const float orig = t[i];
    t[i] = orig + static_cast<float>(eps);
    const double lp = loss();
    t[i] = orig - static_cast<float>(eps);
    const double lm = loss();
    t[i] = orig;
    // Use the actually representable step, not eps, in the quotient.
    const double step = double(orig + static_cast<float>(eps)) - double(orig - static_cast<float>(eps));
    const double num = (lp - lm) / step;
    const double a = analytic[i];
    const double err = std::abs(a - num) / (std::abs(a) + std::abs(num) + floor);
    st.max_err = std::max(st.max_err, err);
    ++st.checked;
    if (err > tol) {
      ++st.bad;
      if (st.bad > max_bad)
        ADD_FAILURE_AT(__FILE__, __LINE__) << what << "[" << i << "]: analytic " << a << " numeric " << num
                                           << " rel.err " << err << " (" << st.bad << " > " << max_bad
                                           << " entries above " << tol << ")";
    }
  }
  return st;
}

/// Linear probe objective L(y) = Σ r_i y_i in double; dL/dy = r.
inline double probe(const Tensor& y, const Tensor& r) {
  double s = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i) s += double(y[i]) * r[i];
  return s;
}

}  // namespace dc::test
