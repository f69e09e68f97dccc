// deepcontact sph-study: how much of the solved contact forces survives the SPH round trip
// particle → grid → particle, over kernels, grid spacings d, supports h/d and normalisation
// modes (docs/sph.md). The study itself is dc_research's (dc/research/sph_study.hpp); this
// command parses the options into an SphStudyDef, runs it, writes its files into --out
// (sph_study.csv, sph_study.md, sph_study_<normalisation>.png) and prints the best setting.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands/cli_common.hpp"
#include "commands/commands.hpp"
#include "dc/bench/list_options.hpp"
#include "dc/core/error.hpp"
#include "dc/io/output_path.hpp"
#include "dc/research/sph_study.hpp"

namespace dc::cli {
namespace {

struct StudyArgs {
  SceneArgs scene;
  std::string seeds = "1..2";
  int steps = 0;       // 0 = the scene's [time] steps
  int every = 1;       // sample every k-th step
  int sweeps = 0;      // 0 = the scene's [solver] sweeps
  double min_lambda = 1e-2;
  std::string kernels = "poly6,spiky,cubic";
  std::string spacings = "1,0.5,0.25";
  std::string ratios = "0.5,0.71,1,1.5,2";
  std::string normalisations = "sum-to-one-legacy,none,shepard";
  std::string out = "sph_study";
};

std::vector<double> parse_doubles(const std::string& text, const char* option) {
  std::vector<double> out;
  for (const auto& item : bench::split_list(text)) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || !std::isfinite(v) || v <= 0)
      throw ConfigError(std::string(option) + ": '" + item + "' is not a positive number");
    out.push_back(v);
  }
  return out;
}

SphStudyDef study_def(const StudyArgs& a) {
  SphStudyDef def;
  def.steps = a.steps;
  def.every = a.every;
  def.sweeps = a.sweeps;
  def.min_lambda = a.min_lambda;
  // The scalar options are checked before the lists are parsed (the lists are still the valid
  // defaults here), so a bad --steps is reported ahead of a bad --kernels.
  def.validate();
  def.seeds = bench::parse_seed_range(a.seeds);
  def.kernels.clear();
  for (const auto& k : bench::split_list(a.kernels)) def.kernels.push_back(parse_sph_kernel(k));
  def.normalisations.clear();
  for (const auto& n : bench::split_list(a.normalisations)) def.normalisations.push_back(parse_sph_normalisation(n));
  def.spacings = parse_doubles(a.spacings, "--spacings");
  def.ratios = parse_doubles(a.ratios, "--ratios");
  return def;
}

void run(const StudyArgs& a) {
  check_output_directory(a.out);  // before the simulations
  const WorldDef scene = a.scene.load();
  const SphStudyDef def = study_def(a);
  const SphStudyResults r = run_sph_study(scene, def, [](std::uint64_t seed, std::size_t frames, std::size_t contacts) {
    std::fprintf(stderr, "sph-study: seed %llu: %zu frames, %zu contacts\n", static_cast<unsigned long long>(seed),
                 frames, contacts);
  });
  const std::string scene_name = a.scene.file.empty() ? std::string("the seed scene") : "`" + a.scene.file + "`";
  write_sph_study(r, a.out, scene_name, a.seeds);
  if (const int rc = plot_sph_study(a.out); rc != 0)
    std::fprintf(stderr, "deepcontact sph-study: warning: plotting failed (exit %d)\n", rc);

  const SphStudyRow& best = best_sph_study_row(r);
  std::printf("best: %s d=%g h/d=%g %s: median relative error %s (p90 %s)\n", to_string(best.s.kernel), best.s.d,
              best.s.ratio, to_string(best.s.normalisation), sph_study_percent(best.median).c_str(),
              sph_study_percent(best.p90).c_str());
  if (const SphStudyRow* legacy = legacy_seed_row(r))
    std::printf("legacy sum-to-one at the seed setting (poly6, d = h = 0.5): median lambda_n retained %.3f\n",
                legacy->retained_n);
  std::printf("report: %s/sph_study.md\n", std::filesystem::path(a.out).string().c_str());
}

}  // namespace

void add_sph_study_command(CLI::App& app) {
  auto args = std::make_shared<StudyArgs>();
  auto* cmd = app.add_subcommand(
      "sph-study", "Measure the SPH particle->grid->particle round-trip error of solved contact forces");
  args->scene.add_options(*cmd);
  cmd->add_option("--seeds", args->seeds, "Scene seeds: A..B, or A,B,C")->capture_default_str();
  cmd->add_option("--steps", args->steps, "Steps per scene (default: the scene's [time] steps)");
  cmd->add_option("--every", args->every, "Use every k-th step")->capture_default_str();
  cmd->add_option("--sweeps", args->sweeps, "Solver sweeps per step (default: the scene's [solver] sweeps)");
  cmd->add_option("--min-lambda", args->min_lambda, "Evaluate contacts with |lambda_n| above this [N]")
      ->capture_default_str();
  cmd->add_option("--kernels", args->kernels, "Kernels (poly6, spiky, cubic, poly6-legacy3d, spiky-legacy3d)")
      ->capture_default_str();
  cmd->add_option("--spacings", args->spacings, "Grid spacings d [m]")->capture_default_str();
  cmd->add_option("--ratios", args->ratios, "Kernel supports as multiples h/d")->capture_default_str();
  cmd->add_option("--normalisations", args->normalisations, "Modes (sum-to-one-legacy, none, shepard)")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Output directory (sph_study.csv, sph_study.md, heat maps)")
      ->capture_default_str();
  cmd->callback([args] { run(*args); });
}

}  // namespace dc::cli
