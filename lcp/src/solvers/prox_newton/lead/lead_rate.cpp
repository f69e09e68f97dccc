#include "solvers/prox_newton/lead/lead_rate.hpp"

#include <cmath>

namespace dc::solvers::prox {

int lead_window_chunks(int window, double reference, int bodies) {
  if (window <= 0 || !(reference > 0) || bodies <= reference) return window;
  return static_cast<int>(std::lround(window * std::sqrt(bodies / reference)));
}

bool LeadRate::go_on(double best, double target, int done, int chunk, int cap) {
  since_best_ = best < (best_.empty() ? start_ : best_.back()) ? 0 : since_best_ + 1;
  best_.push_back(best);
  if (!(best > 0) || !std::isfinite(best) || best <= target || done >= cap) return false;
  if (stall_ > 0 && since_best_ >= stall_) return false;
  const int n = static_cast<int>(best_.size());
  if (window_ == 0) return rate_reaches(best, target, done, chunk, cap);
  if (n <= window_) return best * std::pow(gain_, static_cast<double>(n) / window_) <= start_;
  return best * gain_ <= best_[static_cast<size_t>(n - 1 - window_)];
}

double LeadRate::window_fall() const {
  const int n = static_cast<int>(best_.size());
  if (n == 0 || window_ == 0 || !(best_.back() > 0)) return 1.0;
  if (n <= window_) return std::pow(start_ / best_.back(), static_cast<double>(window_) / n);
  return best_[static_cast<size_t>(n - 1 - window_)] / best_.back();
}

bool LeadRate::rate_reaches(double best, double target, int done, int chunk, int cap) const {
  const int n = static_cast<int>(best_.size());
  const double before = n == 1 ? start_ : best_[static_cast<size_t>(n - 2)];
  if (!(best < before)) return false;
  const double q = n == 1 ? best / start_ : std::pow(best / best_.front(), 1.0 / (n - 1));
  if (!(q < 1)) return false;
  const double chunks_left = std::log(target / best) / std::log(q);
  return done + chunks_left * chunk <= cap;
}

}  // namespace dc::solvers::prox
