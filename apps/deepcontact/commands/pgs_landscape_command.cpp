// deepcontact pgs-landscape: the objective that `train --loss pgs-*` follows, probed on lines
// through builtin's start for several unroll horizons (learning/include/dc/learning/
// pgs_landscape.hpp; docs/research.md "Why long horizons do not train"). It replays the data
// set's simulations as train does (same samples for the same --every/--first-step) and writes
// one CSV row per (sample, horizon), then prints medians over the samples per horizon:
// whether J(ε d) follows the gradient's prediction slope·ε, whether the shortest horizon's
// descent direction still descends at K, and J along the straight path to the least-squares
// grid field G* of the exact correction.
#include <CLI/CLI.hpp>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "dc/bench/bench_statistics.hpp"
#include "commands/commands.hpp"
#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/cnn/data_set.hpp"
#include "dc/research/pgs_landscape.hpp"

namespace dc::cli {
namespace {

using bench::median_of;

struct LandscapeArgs {
  std::string data;
  std::string out = "pgs_landscape.csv";
  std::string loss = "pgs-distance";
  bool gain = false;
  int every = 8;
  int first_step = 0;
  int max_samples = 32;
  int threads = 0;
  PgsLandscapeDef def;
};

void run(const LandscapeArgs& a) {
  PgsLandscapeDef def = a.def;
  def.loss = parse_pgs_loss(a.loss);
  def.validate();
  if (a.every < 1) throw ConfigError("--every must be >= 1");
  if (a.first_step < 0) throw ConfigError("--first-step must be >= 0");
  if (a.max_samples < 1) throw ConfigError("--max-samples must be >= 1");
  if (!std::filesystem::exists(a.data)) throw IoError(a.data + ": no such file");
  if (a.threads > 0) omp_set_num_threads(a.threads);
  const DataSetReader reader(a.data);
  std::vector<int> sims;
  for (const DataSetSimulation& s : reader.simulations()) sims.push_back(s.index);
  std::vector<PgsSample> samples = collect_pgs_samples(reader.params(), sims, a.every, {}, a.first_step,
                                                       a.gain ? LabelKind::Gain : LabelKind::Residual);
  // An even spread over the kept samples when there are more than --max-samples.
  if (static_cast<int>(samples.size()) > a.max_samples) {
    std::vector<PgsSample> kept;
    for (int i = 0; i < a.max_samples; ++i)
      kept.push_back(std::move(samples[static_cast<std::size_t>(i) * samples.size() / a.max_samples]));
    samples = std::move(kept);
  }
  if (samples.empty()) throw ConfigError(a.data + ": no samples at --first-step " + std::to_string(a.first_step));
  std::vector<std::vector<PgsLandscapeLine>> lines(samples.size());
#pragma omp parallel for schedule(dynamic)
  for (std::size_t i = 0; i < samples.size(); ++i) lines[i] = probe_pgs_landscape(samples[i], def);

  std::ostringstream csv;
  csv << "simulation,step,rows,unroll,grad_norm,slope,cos_to_first,cos_to_field";
  for (const double e : def.steps) csv << ",J_own_" << e;
  for (const double e : def.steps) csv << ",J_first_" << e;
  for (const double t : def.path) csv << ",J_field_" << t;
  csv << '\n';
  for (std::size_t i = 0; i < samples.size(); ++i)
    for (const PgsLandscapeLine& L : lines[i]) {
      csv << samples[i].simulation << ',' << samples[i].step << ',' << samples[i].problem.rows() << ',' << L.unroll
          << ',' << L.grad_norm << ',' << L.slope << ',' << L.cos_to_first << ',' << L.cos_to_field;
      for (const double j : L.along_own) csv << ',' << j;
      for (const double j : L.along_first) csv << ',' << j;
      for (const double j : L.along_field) csv << ',' << j;
      csv << '\n';
    }
  write_file_atomically(a.out, csv.str());

  std::printf("pgs-landscape: %s, %s read-back, %zu samples of %s (every %d from step %d) -> %s\n", a.loss.c_str(),
              a.gain ? "gain" : "residual", samples.size(), a.data.c_str(), a.every, a.first_step, a.out.c_str());
  std::printf("medians over the samples; J = 0 is builtin, < 0 better; d = steepest descent of J_K, RMS 1 per grid entry\n");
  for (std::size_t k = 0; k < def.unrolls.size(); ++k) {
    std::vector<double> cf, cg;
    for (const auto& ls : lines) {
      cf.push_back(ls[k].cos_to_first);
      cg.push_back(ls[k].cos_to_field);
    }
    std::printf("K = %d: cos(g_K, g_%d) %.3f, cos(-g_K, G*) %.3f\n", def.unrolls[k], def.unrolls[0], median_of(cf),
                median_of(cg));
    for (std::size_t e = 0; e < def.steps.size(); ++e) {
      std::vector<double> ratio, own, first;
      int down = 0;
      for (const auto& ls : lines) {
        const PgsLandscapeLine& L = ls[k];
        ratio.push_back(L.slope != 0 ? L.along_own[e] / (L.slope * def.steps[e]) : NAN);
        own.push_back(L.along_own[e]);
        first.push_back(L.along_first[e]);
        down += L.along_own[e] < 0;
      }
      std::printf("  eps %-8g J(eps d_K) %+9.4f  actual/predicted %+8.3f  descends on %3.0f %%  J(eps d_%d) %+9.4f\n",
                  def.steps[e], median_of(own), median_of(ratio), 100.0 * down / static_cast<double>(lines.size()),
                  def.unrolls[0], median_of(first));
    }
    for (std::size_t t = 0; t < def.path.size(); ++t) {
      std::vector<double> f;
      for (const auto& ls : lines) f.push_back(ls[k].along_field[t]);
      std::printf("  J(%g G*) %+9.4f\n", def.path[t], median_of(f));
    }
  }
}

}  // namespace

void add_pgs_landscape_command(CLI::App& app) {
  auto args = std::make_shared<LandscapeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "pgs-landscape", "Probe the train-through-PGS objective on lines through builtin's start for several horizons");
  cmd->add_option("--data", args->data, "Data set (deepcontact generate) whose simulations are replayed")->required();
  cmd->add_option("--out", args->out, "CSV, one row per (sample, horizon)")->capture_default_str();
  cmd->add_option("--loss", args->loss, "pgs-distance or pgs-residual")->capture_default_str();
  cmd->add_flag("--gain", args->gain, "Gain read-back (a gain model's output space) instead of the residual one");
  cmd->add_option("--unroll", args->def.unrolls, "Horizons K (comma-separated; the first is the reference)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--steps", args->def.steps, "Step lengths eps along d (RMS per grid entry)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--path", args->def.path, "Points t of the path t G*")->delimiter(',')->capture_default_str();
  cmd->add_option("--cgls-iterations", args->def.cgls_iterations, "CGLS iterations for G*")->capture_default_str();
  cmd->add_option("--pgs-floor", args->def.floor, "f [N] of the objective log(L + rows f^2)")->capture_default_str();
  cmd->add_option("--every", args->every, "Keep every k-th step (as train --every)")->capture_default_str();
  cmd->add_option("--first-step", args->first_step, "First step kept (as train --first-step)")->capture_default_str();
  cmd->add_option("--max-samples", args->max_samples, "At most this many samples, evenly spread")
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "Worker threads (default: OMP_NUM_THREADS or all cores)");
  cmd->callback([args] { run(*args); });
}

}  // namespace dc::cli
