#pragma once
// Non-monotone line-search reference (Grippo–Lampariello–Lucidi): the largest of the merits
// φ = ½‖s·H‖² at the last `size` iterates newton-sparse moved to (NewtonSparseDef::
// nonmonotone_window). An Armijo test against it instead of against φ(λ_k) lets a semismooth
// Newton step cross a mode switch where the non-smooth merit rises for an iteration, instead of
// failing the line search and damping the free block.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace dc::solvers {

class MeritWindow {
 public:
  explicit MeritWindow(int size) : size_(std::max(0, size)) {}
  /// Records the merit at a new iterate (after an accepted step, fallback sweeps or the start).
  void push(double merit) {
    if (size_ == 0) return;
    if (static_cast<int>(last_.size()) == size_) last_.erase(last_.begin());
    last_.push_back(merit);
  }
  /// The reference the Armijo test compares against: max(φ(λ_k), the recorded merits).
  [[nodiscard]] double reference(double current) const {
    double r = current;
    for (const double m : last_) r = std::max(r, m);
    return r;
  }
  /// Forgets the history (the next tests are monotone until merits are recorded again).
  void clear() { last_.clear(); }

 private:
  int size_;
  std::vector<double> last_;
};

}  // namespace dc::solvers
