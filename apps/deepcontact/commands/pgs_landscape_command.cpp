// deepcontact pgs-landscape: the objective that `train --loss pgs-*` follows, probed on lines
// through builtin's start for several unroll horizons (docs/research.md "Why long horizons do
// not train"). The study is dc_research's (dc/research/pgs_landscape_study.hpp: replay the data
// set as train does, probe, take medians); this command parses the options, runs it, writes
// the CSV (one row per sample and horizon) and prints the medians per horizon.
#include <CLI/CLI.hpp>
#include <omp.h>

#include <cstdio>
#include <memory>
#include <string>

#include "commands/cli_common.hpp"
#include "commands/commands.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/io/output_path.hpp"
#include "dc/research/pgs_landscape_study.hpp"

namespace dc::cli {
namespace {

struct LandscapeArgs {
  std::string out = "pgs_landscape.csv";
  std::string loss = "pgs-distance";
  int threads = 0;
  PgsLandscapeStudyDef study;
};

void print_medians(const PgsLandscapeStudy& study) {
  const int first_unroll = study.def.probe.unrolls[0];
  for (const PgsLandscapeHorizonMedians& h : pgs_landscape_medians(study)) {
    std::printf("K = %d: cos(g_K, g_%d) %.3f, cos(-g_K, G*) %.3f\n", h.unroll, first_unroll, h.cos_to_first,
                h.cos_to_field);
    for (const PgsLandscapeStepMedians& m : h.steps)
      std::printf("  eps %-8g J(eps d_K) %+9.4f  actual/predicted %+8.3f  descends on %3.0f %%  J(eps d_%d) %+9.4f\n",
                  m.step, m.along_own, m.actual_over_predicted, m.descends_percent, first_unroll, m.along_first);
    for (std::size_t t = 0; t < h.along_field.size(); ++t)
      std::printf("  J(%g G*) %+9.4f\n", study.def.probe.path[t], h.along_field[t]);
  }
}

void run(const LandscapeArgs& a) {
  check_output_file(a.out);  // before the simulations are replayed
  check_output_extension("--out", a.out, {".csv"}, "a CSV table");
  PgsLandscapeStudyDef def = a.study;
  def.probe.loss = parse_pgs_loss(a.loss);
  def.validate();  // ahead of the thread count: a bad option is reported first
  if (a.threads > 0) omp_set_num_threads(a.threads);
  const PgsLandscapeStudy study = run_pgs_landscape_study(def);
  write_file_atomically(a.out, pgs_landscape_csv(study));

  std::printf("pgs-landscape: %s, %s read-back, %zu samples of %s (every %d from step %d) -> %s\n", a.loss.c_str(),
              def.gain ? "gain" : "residual", study.samples.size(), def.data.c_str(), def.every, def.first_step,
              a.out.c_str());
  std::printf("medians over the samples; J = 0 is builtin, < 0 better; d = steepest descent of J_K, RMS 1 per grid entry\n");
  print_medians(study);
}

}  // namespace

void add_pgs_landscape_command(CLI::App& app) {
  auto args = std::make_shared<LandscapeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "pgs-landscape", "Probe the train-through-PGS objective on lines through builtin's start for several horizons");
  cmd->add_option("--data", args->study.data, "Data set (deepcontact generate) whose simulations are replayed")->required();
  cmd->add_option("--out", args->out, "CSV, one row per (sample, horizon)")->capture_default_str();
  cmd->add_option("--loss", args->loss, "pgs-distance or pgs-residual")->capture_default_str();
  cmd->add_flag("--gain", args->study.gain, "Gain read-back (a gain model's output space) instead of the residual one");
  cmd->add_option("--unroll", args->study.probe.unrolls, "Horizons K (comma-separated; the first is the reference)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--steps", args->study.probe.steps, "Step lengths eps along d (RMS per grid entry)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--path", args->study.probe.path, "Points t of the path t G*")->delimiter(',')->capture_default_str();
  cmd->add_option("--cgls-iterations", args->study.probe.cgls_iterations, "CGLS iterations for G*")->capture_default_str();
  cmd->add_option("--pgs-floor", args->study.probe.floor, "f [N] of the objective log(L + rows f^2)")->capture_default_str();
  cmd->add_option("--every", args->study.every, "Keep every k-th step (as train --every)")->capture_default_str();
  cmd->add_option("--first-step", args->study.first_step, "First step kept (as train --first-step)")->capture_default_str();
  cmd->add_option("--max-samples", args->study.max_samples, "At most this many samples, evenly spread")
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "Worker threads (default: OMP_NUM_THREADS or all cores)");
  cmd->callback([args] { run(*args); });
}

}  // namespace dc::cli
