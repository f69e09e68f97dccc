#pragma once
// `deepcontact train --loss pgs-residual|pgs-distance|pgs-field`: the solver-unrolled training of a
// residual model (dc/research/pgs_training_run.hpp; docs/learning.md "Training through PGS").
// train_command.cpp owns the shared options and dispatches here when --loss is not regression.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace dc::cli {

/// The options only this path has.
struct PgsTrainOptions {
  std::string loss = "regression";  // regression | pgs-residual | pgs-distance | pgs-field
  int unroll = 20;                  // k sweeps unrolled
  std::string init;                 // the residual model to start from (required for pgs-*)
  double time_limit = 0;            // [s] of training, 0 = none
  double floor = 1e-2;              // f [N] of the objective's ε = rows·f²
  double clip = 1.0;                // global gradient-norm clip (0 = off)
  bool gain = false;                // train a gain model (LabelKind::Gain) from the residual --init
  int field_iterations = 100;       // pgs-field: CGLS iterations of the target field G*
};

/// Registers --loss, --unroll, --init, --time-limit, --pgs-floor, --clip, --gain, --field-iterations on `cmd`.
void add_pgs_train_options(CLI::App* cmd, PgsTrainOptions& o);

/// The shared options of `train` that the PGS path uses.
struct PgsTrainCommon {
  std::string data, out;
  int epochs = 0, batch = 0, threads = 0, every = 1, first_step = 0;
  double lr = 0, momentum = 0, weight_decay = 0, val = 0, deadzone = 0;
  std::uint64_t seed = 1;
  bool force = false;
};

void run_train_through_pgs(const PgsTrainOptions& o, const PgsTrainCommon& c);

}  // namespace dc::cli
