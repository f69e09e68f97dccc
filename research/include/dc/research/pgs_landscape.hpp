#pragma once
// PgsLandscape: how the solver-unrolled objective J_K of one sample (pgs_trainer.hpp) behaves
// on lines through builtin's start G = 0, for several horizons K — the diagnostic of why
// long horizons do not train (docs/research.md "Why long horizons do not train").
//
// For each horizon K, at G = 0 (builtin, J_K = 0 exactly):
//   g_K = dJ_K/dG               the reverse-mode gradient the trainer follows (2·ny·nx entries),
//   d_K = −g_K / rms(g_K)        steepest descent scaled to RMS 1 per grid entry,
//   slope_K = g_K·d_K = −‖g_K‖·√n   what the gradient predicts: J_K(ε d_K) ≈ slope_K·ε,
//   J_K(ε d_K) for ε in `steps`  the line a gradient step moves along,
//   J_K(ε d_1)                   along the SHORTEST horizon's descent direction (is the
//                                direction that K_1 sweeps reward still downhill after K?),
//   J_K(t G*) for t in `path`    along the straight path to G*, the least-squares grid field
//                                of the exact correction (below): is the way to a good
//                                field downhill for the objective at K?
//   cos(g_K, g_1), cos(−g_K, G*) does the gradient at K point where the short horizon's does,
//                                and towards the good field?
// G* = argmin ‖R G − δ‖₂ with R the sample's read-back (ContactReadback: Shepard or gain) and
// δ = (λ* − λ_prev) per contact pair, by CGLS from G = 0 (`cgls_iterations` iterations:
// early stopping is the regularisation; the nodes no contact sees stay 0). It is the best
// field of the model's own output space in the least-squares sense, i.e. what a perfect
// network of this parametrisation would be trained towards by a regression loss.
//
// Where the unrolled map is smooth at the scale of a step, J(ε d)/ε stays near the slope up
// to the ε a step takes; where PGS's piecewise-linear pieces (one per active set of the K
// sweeps) are small at that scale, J(ε d) is not predicted by the gradient beyond a tiny ε,
// and a gradient method cannot follow the objective.
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
