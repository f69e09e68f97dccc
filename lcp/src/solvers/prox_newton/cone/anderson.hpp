#pragma once
// Anderson acceleration (Walker & Ni's type II, "Anderson mixing") of a fixed-point iteration
// x ← T(x), for prox-newton's exact-cone passes (cone_passes.hpp): from the last m pairs
// (x_j, g_j = T(x_j)) with residuals f_j = g_j − x_j, the next point is
//     x_{k+1} = g_k − ΔG γ,   γ = argmin_γ ‖f_k − ΔF γ‖₂,
// ΔF, ΔG the differences of consecutive f and g. On a locally affine T (fixed active sets)
// this is GMRES on x − T(x) = 0, so a linearly converging iteration speeds up to the few
// slow modes it has. The least squares is solved on its m×m normal equations with a relative
// Tikhonov term 1e-12·trace (ΔF nearly rank deficient near convergence). Sums run in index
// order (the same iterates in every build).
#include <Eigen/Core>
#include <deque>

namespace dc::solvers::prox {

class Anderson {
 public:
  explicit Anderson(int depth) : depth_(depth) {}
  /// Forgets the history (after a step that made things worse).
  void restart() {
    x_.clear();
    g_.clear();
  }
  /// Records the pair (x, g = T(x)) and returns the next point (g itself while the history is
  /// empty or depth is 0).
  Eigen::VectorXd next(const Eigen::VectorXd& x, const Eigen::VectorXd& g);

 private:
  int depth_;
  std::deque<Eigen::VectorXd> x_, g_;  // the last depth + 1 pairs, oldest first
};

}  // namespace dc::solvers::prox
