#pragma once
// Training the warm start through the solver (docs/design.md §8.5; docs/learning.md "Training
// through PGS"). Per sample: y → z = y·σ + m → G = s·sinh(z) → v = R G (ContactReadback) →
// λ⁰ = proj(λ_prev + v) → k sweeps (UnrolledPgs) → L_k (pgs-residual: Σ r_i²; pgs-distance:
// Σ (λ_k − λ*)²), and J = log(L_k + ε) − log(L_k^builtin + ε), ε = rows·f² (f = `floor` [N]).
// PGS pays sweeps in proportion to log(error), so J is the sweeps saved (J < 0) or lost
// against builtin, on one scale for resting and impacted steps. Every map is piecewise linear
// except sinh: the gradient is exact almost everywhere. Only residual models train this way
// (output 0 is builtin, J = 0); the --init model fixes architecture, grid, standardisation and
// label scale. Its dead zone is not applied in training (its zero derivative would stop the
// gradient at the start).
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <span>
#include <string_view>
#include <vector>

#include "dc/learning/model.hpp"
#include "dc/research/pgs_samples.hpp"
#include "dc/research/unrolled_pgs.hpp"

namespace dc {

enum class PgsLoss {
  Residual,  ///< "pgs-residual": scaled natural-map residual after k sweeps (no λ* needed)
  Distance,  ///< "pgs-distance": ‖λ_k − λ*‖² after k sweeps
  /// "pgs-field": no sweeps in the training loss — regress the output grid G on G*, the
  /// read-back's least-squares field of λ* − λ_prev (least_squares_field.hpp), as
  /// L = Σ (G − G*)² over the grid entries some contact reads (Rᵀ1 ≠ 0; the others never
  /// reach PGS). The unrolled map's gradient is short-ranged and points
  /// away from G* at long horizons (docs/research.md "Why long horizons do not train") while
  /// the straight path to G* is downhill for every horizon: this loss takes that path.
  /// Validation (and so the epoch kept) is J_k of pgs-distance, what PGS pays.
  Field,
};
const char* to_string(PgsLoss loss);
/// "pgs-residual" / "pgs-distance" / "pgs-field"; ConfigError otherwise.
PgsLoss parse_pgs_loss(std::string_view text);
/// The loss validation measures: `loss` itself, or pgs-distance for the field loss.
PgsLoss validation_loss(PgsLoss loss);

/// λ⁰ = proj(λ_prev + v) of the solver's bounds (project_feasible's order: normal rows, then
/// friction rows against the projected λ_n), with the adjoint of the projection.
class GuessProjection {
 public:
  /// λ⁰ from λ_prev + v (rows); records the pieces.
  Eigen::VectorXd forward(const LcpProblem& p, const Eigen::VectorXd& unprojected);
  /// dL/d(unprojected) from dL/dλ⁰.
  [[nodiscard]] Eigen::VectorXd backward(const LcpProblem& p, const Eigen::VectorXd& dlam0) const;

 private:
  std::vector<std::int8_t> piece_;  // 0 interior, 1 fixed, 2 at +μλ_n, 3 at −μλ_n
};

/// The objective J of one sample as a function of the raw correction grid G (the model's
/// predict() output, 2·ny·nx floats, NCHW). For the field loss L = Σ_seen (G − G*)² and
/// "builtin's" L is Σ_seen G*² (G = 0), so J < 0 still means closer than builtin; ε is then
/// (seen entries)·f² (f in the field's unit: N·s, or a gain) and `unroll` is unused.
class PgsObjective {
 public:
  /// `field_iterations`: CGLS iterations of G* (field loss only, ≥ 1).
  PgsObjective(const PgsSample& sample, PgsLoss loss, int unroll, double floor = 1e-2, int field_iterations = 100);
  /// J(G); when dgrid is non-null, adds dJ/dG to it (2·ny·nx floats).
  double evaluate(const float* grid, float* dgrid);
  /// L_k from builtin's own start (v = 0).
  [[nodiscard]] double builtin_loss() const { return builtin_loss_; }
  /// L_k of the last evaluate().
  [[nodiscard]] double last_loss() const { return last_loss_; }
  /// λ⁰ = proj(λ_prev + R G), as the cnn starter forms it for a residual model without dead zone.
  Eigen::VectorXd initial_guess(const float* grid);

 private:
  double loss_and_grad(const Eigen::VectorXd& lambda0, Eigen::VectorXd* dlam0);

  const PgsSample& s_;
  PgsLoss loss_;
  int unroll_;
  double eps_;
  UnrolledPgs pgs_;
  GuessProjection proj_;
  std::vector<float> field_;          // G* (field loss only)
  std::vector<std::uint32_t> seen_;  // the grid entries a contact reads (field loss only)
  double builtin_loss_ = 0, last_loss_ = 0;
  std::vector<double> v_, dv_;
};

struct PgsTrainDef {
  PgsLoss loss = PgsLoss::Residual;
  int unroll = 20;                  ///< k ≥ 1 sweeps unrolled
  int epochs = 4;                   ///< ≥ 1
  int batch = 8;                    ///< samples per SGD step (the unroll is per sample)
  double learning_rate = 1e-3;      ///< > 0
  double momentum = 0.9;            ///< [0, 1)
  double weight_decay = 1e-4;       ///< ≥ 0
  double validation_fraction = 0.2; ///< of the simulations, drawn as the regression trainer draws them
  std::uint64_t seed = 1;           ///< split, shuffles, dropout
  double time_limit = 0;            ///< [s] of training (0 = none): stop before the next minibatch
  double floor = 1e-2;              ///< f [N] of ε = rows·f²
  /// Global gradient-norm clip (0 = off): the minibatch gradient is scaled to norm ≤ clip
  /// before the SGD step. J's gradient spans orders of magnitude between a step that PGS has
  /// nearly solved and one it has not; the clip bounds the step the worst one can take.
  double clip = 1.0;
  /// CGLS iterations of the field loss's G* (least_squares_field.hpp; ≥ 1): 100 is the
  /// minimum-norm fit the landscape probe measured J(G*) of, a few give a smoother field.
  int field_iterations = 100;
  /// ConfigError naming the option.
  void validate() const;
};

struct PgsEpochReport {
  int epoch = 0;
  double train_objective = 0;       ///< mean J over the epoch's training samples (before each update)
  double validation_objective = 0;  ///< mean J over the validation samples (inference mode); NaN without
  double validation_improved = 0;   ///< share of validation samples with J < 0
  double seconds = 0;
  int clipped = 0;                  ///< minibatches whose gradient was clipped
  int skipped = 0;                  ///< minibatches skipped for a non-finite gradient
  double grad_norm = 0;             ///< mean global gradient norm of the minibatches (before clipping)
};

/// The validation simulation ids of `sims` (distinct ids of the samples) for `def`: the same
/// draw as Trainer::pick_validation_simulations with Rng(def.seed).
std::vector<int> pgs_validation_simulations(std::span<const PgsSample> samples, const PgsTrainDef& def);

/// Trains `model` (a residual model) on `samples`. `on_epoch` is called after each epoch with
/// the report and may return false to stop; `keep_going` is polled before each minibatch.
/// Returns the reports. ConfigError for an absolute model, InvalidArgument for a sample whose
/// feature shape differs from the model's input.
std::vector<PgsEpochReport> train_through_pgs(Model& model, std::span<const PgsSample> samples, const PgsTrainDef& def,
                                              const std::function<bool(const PgsEpochReport&)>& on_epoch = {},
                                              const std::function<bool()>& keep_going = {});

/// Mean J of `model` over samples[idx] (inference mode) for validation_loss(def.loss), and the
/// share with J < 0.
std::pair<double, double> pgs_objective_mean(Model& model, std::span<const PgsSample> samples,
                                             std::span<const std::size_t> idx, const PgsTrainDef& def);

}  // namespace dc
