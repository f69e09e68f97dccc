#pragma once
// PgsLandscape: how the solver-unrolled objective J_K of one sample (pgs_trainer.hpp) behaves
// on lines through builtin's start G = 0 for several horizons K — the diagnostic of why long
// horizons do not train (docs/research.md "Why long horizons do not train"). Per K: the
// gradient g_K, the RMS-1 descent direction d_K, the predicted slope, J_K along d_K, along the
// shortest horizon's d_1 and along the straight path to G*, and the cosines between them
// (docs/learning.md "The objective's landscape"). G* = argmin ‖R G − δ‖₂ (R the read-back,
// δ = λ* − λ_prev per contact) by CGLS from G = 0, early stopping as the regularisation: the
// field a perfect network would be regressed towards.
#include <vector>

#include "dc/research/least_squares_field.hpp"
#include "dc/research/pgs_samples.hpp"
#include "dc/research/pgs_trainer.hpp"

namespace dc {

struct PgsLandscapeDef {
  PgsLoss loss = PgsLoss::Distance;
  /// Horizons K ≥ 1, the first is the reference direction d_1 (say the training horizon).
  std::vector<int> unrolls{100, 400, 1000};
  /// ε > 0: RMS change per grid entry along d (a gain for gain models, N for residual ones).
  std::vector<double> steps{1e-5, 1e-4, 1e-3, 1e-2, 3e-2, 1e-1, 3e-1};
  /// t along the path G = t G* (t = 1 is G*).
  std::vector<double> path{0.25, 0.5, 0.75, 1.0};
  int cgls_iterations = 100;  ///< ≥ 1
  double floor = 1e-2;        ///< f [N] of the objective's ε = rows·f² (pgs_trainer.hpp)
  /// ConfigError naming the option.
  void validate() const;
};

/// The landscape of one sample at one horizon.
struct PgsLandscapeLine {
  int unroll = 0;
  double grad_norm = 0;        ///< ‖g_K‖₂
  double slope = 0;            ///< g_K·d_K (< 0)
  double cos_to_first = 0;     ///< cos(g_K, g_1) (1 for the first horizon)
  double cos_to_field = 0;     ///< cos(−g_K, G*)
  std::vector<double> along_own;    ///< J_K(ε d_K), one per step
  std::vector<double> along_first;  ///< J_K(ε d_1), one per step
  std::vector<double> along_field;  ///< J_K(t G*), one per path entry
};

/// The lines of `sample` for every horizon of `def` (validated; InvalidArgument for the
/// distance loss without λ*). G* is computed once per sample. Thread-safe for distinct samples.
std::vector<PgsLandscapeLine> probe_pgs_landscape(const PgsSample& sample, const PgsLandscapeDef& def);

}  // namespace dc
