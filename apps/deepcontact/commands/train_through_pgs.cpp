// deepcontact train --loss pgs-*: the options only this path has, and the run of
// dc/research/pgs_training_run.hpp (replay the data set, start from the --init residual model,
// train through k unrolled PGS sweeps; OUT and OUT.loss.csv) wired to the terminal: its
// progress lines printed, Ctrl-C stopping it.
#include "commands/train_through_pgs.hpp"

#include <omp.h>

#include <cstdio>
#include <optional>

#include "cluster/sigint_guard.hpp"
#include "dc/research/pgs_training_run.hpp"

namespace dc::cli {

void add_pgs_train_options(CLI::App* cmd, PgsTrainOptions& o) {
  cmd->add_option("--loss", o.loss,
                  "regression (MSE on the label grids, the default) or pgs-residual / pgs-distance: train a "
                  "residual --init model through --unroll PGS sweeps (docs/learning.md 'Training through PGS'); "
                  "pgs-field: regress its output on the read-back's least-squares field of lambda* - lambda_prev, "
                  "validated by pgs-distance after --unroll sweeps")
      ->capture_default_str();
  cmd->add_option("--unroll", o.unroll, "pgs-*: PGS sweeps unrolled per sample")->capture_default_str();
  cmd->add_option("--init", o.init, "pgs-*: the residual model to start from (arch, grid, statistics)");
  cmd->add_option("--time-limit", o.time_limit, "pgs-*: stop training after this many seconds (0 = none)")
      ->capture_default_str();
  cmd->add_option("--pgs-floor", o.floor, "pgs-*: f [N] of the objective log(L + rows f^2)")->capture_default_str();
  cmd->add_option("--clip", o.clip, "pgs-*: clip the minibatch gradient to this global norm (0 = off)")
      ->capture_default_str();
  cmd->add_option("--field-iterations", o.field_iterations,
                  "pgs-field: CGLS iterations of the target field (fewer = smoother; least_squares_field.hpp)")
      ->capture_default_str();
  cmd->add_flag("--gain", o.gain,
                "pgs-*: train a GAIN model, lambda0 = lambda_prev (1 + read-back of a gain field), from the residual "
                "--init (its trunk kept, its output layer zeroed: training starts at builtin; docs/learning.md)");
}

namespace {

PgsTrainingRunDef run_def(const PgsTrainOptions& o, const PgsTrainCommon& c) {
  PgsTrainingRunDef def;
  def.data = c.data;
  def.init = o.init;
  def.out = c.out;
  def.train.loss = parse_pgs_loss(o.loss);
  def.train.unroll = o.unroll;
  def.train.epochs = c.epochs;
  def.train.batch = c.batch;
  def.train.learning_rate = c.lr;
  def.train.momentum = c.momentum;
  def.train.weight_decay = c.weight_decay;
  def.train.validation_fraction = c.val;
  def.train.seed = c.seed;
  def.train.time_limit = o.time_limit;
  def.train.floor = o.floor;
  def.train.clip = o.clip;
  def.train.field_iterations = o.field_iterations;
  def.every = c.every;
  def.first_step = c.first_step;
  def.deadzone = c.deadzone;
  def.gain = o.gain;
  def.force = c.force;
  return def;
}

/// The progress lines of the run; SIGINT stops it once the replay starts (before that, while
/// the data set and --init load, Ctrl-C ends the process as usual).
PgsTrainingHooks printing_hooks(const PgsTrainingRunDef& def, std::optional<SigintGuard>& sigint) {
  const PgsTrainDef& t = def.train;
  PgsTrainingHooks h;
  h.keep_going = [] { return !interrupted(); };
  h.on_replay_start = [&sigint] { sigint.emplace(); };
  h.on_replayed = [&def, &t](const PgsReplayReport& r) {
    std::printf("train: %s, unroll %d: replayed %zu simulations of %s -> %zu samples (every %d) in %.1f s; "
                "start %s, dead zone %g N, %d epochs, batch %d, lr %g, time limit %g s\n",
                to_string(t.loss), t.unroll, r.simulations, def.data.c_str(), r.samples, def.every, r.seconds,
                def.init.c_str(), def.deadzone, t.epochs, t.batch, t.learning_rate, t.time_limit);
    std::fflush(stdout);
  };
  h.on_init = [&t](const PgsInitReport& r) {
    std::printf("train: the --init model: validation objective %.4f (%.0f %% of steps better than builtin after %d "
                "sweeps; 0 = builtin, log-units of the %s loss)\n", r.objective, 100 * r.better_share, t.unroll,
                to_string(validation_loss(t.loss)));
    std::fflush(stdout);
  };
  h.on_epoch = [&t](const PgsEpochReport& r, bool improved) {
    std::printf("epoch %3d/%d  train %.4f  val %.4f (%.0f %% better than builtin)  |g| %.3g, %d clipped, %d skipped  %.1f s%s\n",
                r.epoch + 1, t.epochs, r.train_objective, r.validation_objective, 100 * r.validation_improved,
                r.grad_norm, r.clipped, r.skipped, r.seconds, improved ? "  *best" : "");
    std::fflush(stdout);
  };
  return h;
}

}  // namespace

void run_train_through_pgs(const PgsTrainOptions& o, const PgsTrainCommon& c) {
  const PgsTrainingRunDef def = run_def(o, c);
  def.validate();  // before the thread count, so that a bad option is the one reported
  std::optional<SigintGuard> sigint;
  const PgsTrainingHooks hooks = printing_hooks(def, sigint);
  if (c.threads > 0) omp_set_num_threads(c.threads);
  const PgsTrainingOutcome r = run_pgs_training(def, hooks);
  if (r.replay_interrupted) {
    std::fprintf(stderr, "deepcontact: interrupted while replaying the simulations; nothing written\n");
    return;
  }
  std::printf("train: best epoch %d of %zu (objective %.4f); %.1f s of training -> %s (%s.loss.csv)\n",
              r.best_epoch + 1, r.epochs, r.best, r.seconds, c.out.c_str(), c.out.c_str());
  // The file holds the best *trained* epoch; say so when that is worse than where it started.
  if (r.worse_than_init())
    std::fprintf(stderr,
                 "deepcontact: warning: no epoch beat the --init model's validation objective (%.4f; best epoch "
                 "%.4f): %s is worse than --init on the validation steps (try a smaller --lr)\n",
                 r.init_objective, r.best, c.out.c_str());
}

}  // namespace dc::cli
