// deepcontact sph-study: how much of the solved contact forces survives the SPH round trip
// particle → grid → particle, over kernels, grid spacings d, supports h/d and normalisation
// modes (docs/sph.md). This is the ceiling of every grid-based warm start (sph, cnn): the
// error measured here is what the grid alone costs, before any learning.
//
// For each scene seed the seed scene (or --scene) is simulated with the scene's solver;
// after each step the contacts carry their solved λ = (λ_n, λ_t) at their points. Every
// setting then splats all contacts of a step and reads them back at the contact points;
// the relative error |λ_rt − λ|₂ / |λ|₂ is collected over contacts with |λ_n| > --min-lambda.
// Outputs in --out: sph_study.csv (one row per setting), sph_study.md (tables, best
// setting, legacy loss) and sph_study_<normalisation>.png heat maps (research/plots/sph_study.py).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "commands/cli_common.hpp"
#include "commands/commands.hpp"
#include "dc/bench/list_options.hpp"
#include "dc/research/research_starters.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "dc/sph/sph_transfer.hpp"

namespace dc::cli {
namespace {

namespace fs = std::filesystem;

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

/// One step's contacts: points and particle-major (λ_n, λ_t).
struct Frame {
  std::vector<Vec2> points;
  std::vector<double> lambda;
};

struct Setting {
  SphKernelType kernel;
  double d, ratio;
  SphNormalisation norm;
};

struct Row {
  Setting s;
  std::size_t contacts = 0;     // evaluated contacts (|λ_n| > threshold)
  double median = 0, p90 = 0, mean = 0;  // relative error |λ_rt − λ| / |λ|
  double median_n = 0;          // median |λ_rt,n − λ_n| / |λ_n|
  double retained_n = 0;        // median λ_rt,n / λ_n
  double unsupported = 0;       // share of evaluated contacts flagged unsupported (Shepard)
  double seconds = 0;           // wall time of all round trips of this setting
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

double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// Simulates one seed; returns the sampled frames (steps with at least one contact).
std::vector<Frame> simulate(WorldDef def, const LcpSolver& solver, const SolverOptions& opt, int every) {
  World world(std::move(def));
  std::vector<Frame> frames;
  // Built-in warm start (previous λ by contact key): the study needs well-converged λ, not
  // a solver benchmark, and this converges the fixed sweep budget furthest.
  const World::InitialGuess guess = [](const World& w) {
    std::unordered_map<ContactKey, std::pair<double, double>, ContactKeyHash> prev;
    for (const Contact& c : w.previous_contacts()) prev[c.key] = {c.lambda_n, c.lambda_t};
    std::vector<double> ln(w.contacts().size(), 0.0), lt(w.contacts().size(), 0.0);
    for (std::size_t c = 0; c < w.contacts().size(); ++c)
      if (const auto it = prev.find(w.contacts()[c].key); it != prev.end()) {
        ln[c] = it->second.first;
        lt[c] = it->second.second;
      }
    return w.pack(ln, lt);
  };
  const int steps = world.def().time.steps;
  for (int s = 0; s < steps; ++s) {
    world.step(solver, opt, guess);
    if ((s + 1) % every != 0 || world.contacts().empty()) continue;
    Frame f;
    for (const Contact& c : world.contacts()) {
      f.points.push_back(c.point);
      f.lambda.push_back(c.lambda_n);
      f.lambda.push_back(c.lambda_t);
    }
    frames.push_back(std::move(f));
  }
  return frames;
}

Row evaluate(const Setting& s, const WorldDef& def, const std::vector<Frame>& frames, double min_lambda,
             std::vector<double>& err, std::vector<double>& err_n, std::vector<double>& kept) {
  SphTransferDef td;
  td.grid = SphGridDef{def.world.width, def.world.height, s.d, 2};
  td.kernel = s.kernel;
  td.support = s.ratio * s.d;
  td.normalisation = s.norm;
  SphTransfer t(td);
  err.clear();
  err_n.clear();
  kept.clear();
  std::size_t flagged = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (const Frame& f : frames) {
    const auto rt = t.round_trip(f.points, f.lambda);
    const auto flags = t.unsupported();
    for (std::size_t c = 0; c < f.points.size(); ++c) {
      const double ln = f.lambda[2 * c], lt = f.lambda[2 * c + 1];
      if (!(std::abs(ln) > min_lambda)) continue;
      const double en = rt[2 * c] - ln, et = rt[2 * c + 1] - lt;
      err.push_back(std::hypot(en, et) / std::hypot(ln, lt));
      err_n.push_back(std::abs(en) / std::abs(ln));
      kept.push_back(rt[2 * c] / ln);
      flagged += flags[c];
    }
  }
  Row r;
  r.s = s;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.contacts = err.size();
  double sum = 0;
  for (const double e : err) sum += e;
  r.mean = err.empty() ? std::numeric_limits<double>::quiet_NaN() : sum / err.size();
  r.median = quantile(err, 0.5);
  r.p90 = quantile(err, 0.9);
  r.median_n = quantile(err_n, 0.5);
  r.retained_n = quantile(kept, 0.5);
  r.unsupported = err.empty() ? 0.0 : static_cast<double>(flagged) / err.size();
  return r;
}

std::string pct(double v) {
  std::ostringstream os;
  if (!std::isfinite(v)) return "n/a";
  if (v == 0.0) return "0 %";
  if (v < 1e-4) os << std::scientific << std::setprecision(1) << 100 * v << " %";
  else os << std::fixed << std::setprecision(v < 0.1 ? 2 : 1) << 100 * v << " %";
  return os.str();
}

/// Shortest round-trip-ish text of a setting parameter (0.5, 0.71, 1).
std::string num(double v, int digits = 6) {
  std::ostringstream os;
  os << std::defaultfloat << std::setprecision(digits) << v;
  return os.str();
}

/// Errors below this are rounding (an exact round trip): ranked as equal.
constexpr double kExact = 1e-9;

void write_file(const fs::path& p, const std::string& text) {
  std::ofstream f(p);
  f << text;
  if (!f) throw IoError(p.string() + ": cannot write");
}

void run(const StudyArgs& a) {
  WorldDef def = a.scene.load();
  if (a.steps < 0) throw ConfigError("--steps must be >= 0");
  if (a.steps > 0) def.time.steps = a.steps;
  if (a.every < 1) throw ConfigError("--every must be >= 1");
  if (a.sweeps < 0) throw ConfigError("--sweeps must be >= 0");
  if (!(a.min_lambda >= 0) || !std::isfinite(a.min_lambda)) throw ConfigError("--min-lambda must be finite and >= 0");
  const auto seeds = bench::parse_seed_range(a.seeds);
  std::vector<SphKernelType> kernels;
  for (const auto& k : bench::split_list(a.kernels)) kernels.push_back(parse_sph_kernel(k));
  std::vector<SphNormalisation> norms;
  for (const auto& n : bench::split_list(a.normalisations)) norms.push_back(parse_sph_normalisation(n));
  const auto spacings = parse_doubles(a.spacings, "--spacings");
  const auto ratios = parse_doubles(a.ratios, "--ratios");
  // Validate every grid before the (long) simulation.
  for (const double d : spacings) SphGridDef{def.world.width, def.world.height, d, 2}.validate();

  const auto solver = make_solver(def.solver.name);
  SolverOptions opt = solver_options(def.solver);
  if (a.sweeps > 0) opt.max_sweeps = a.sweeps;
  opt.record_theta = false;

  const auto t_sim = std::chrono::steady_clock::now();
  std::vector<Frame> frames;
  std::size_t contacts = 0;
  for (const auto seed : seeds) {
    WorldDef d = def;
    d.bodies.seed = seed;
    auto f = simulate(d, *solver, opt, a.every);
    std::size_t nc = 0;
    for (const auto& fr : f) nc += fr.points.size();
    std::fprintf(stderr, "sph-study: seed %llu: %zu frames, %zu contacts\n",
                 static_cast<unsigned long long>(seed), f.size(), nc);
    contacts += nc;
    for (auto& fr : f) frames.push_back(std::move(fr));
  }
  const double sim_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_sim).count();
  if (frames.empty()) throw ConfigError("sph-study: the simulation produced no contacts (nothing to study)");

  std::vector<Row> rows;
  std::vector<double> err, err_n, kept;
  for (const auto norm : norms)
    for (const auto kernel : kernels)
      for (const double d : spacings)
        for (const double ratio : ratios)
          rows.push_back(evaluate(Setting{kernel, d, ratio, norm}, def, frames, a.min_lambda, err, err_n, kept));
  if (rows.front().contacts == 0)
    throw ConfigError("sph-study: no contact has |lambda_n| > --min-lambda");

  const fs::path dir(a.out);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(dir.string() + ": cannot create directory: " + ec.message());

  // ---- CSV ---------------------------------------------------------------------------
  std::ostringstream csv;
  csv << "kernel,d,h_over_d,h,normalisation,contacts,median_rel_error,p90_rel_error,mean_rel_error,"
         "median_rel_error_n,median_retained_n,unsupported_share,seconds\n";
  csv << std::setprecision(10);
  for (const Row& r : rows)
    csv << to_string(r.s.kernel) << ',' << r.s.d << ',' << r.s.ratio << ',' << r.s.ratio * r.s.d << ','
        << to_string(r.s.norm) << ',' << r.contacts << ',' << r.median << ',' << r.p90 << ',' << r.mean << ','
        << r.median_n << ',' << r.retained_n << ',' << r.unsupported << ',' << r.seconds << '\n';
  write_file(dir / "sph_study.csv", csv.str());

  // ---- Markdown ------------------------------------------------------------------------
  // Ranking: median error, then mean error (both floored at kExact: below it the round trip
  // is exact up to rounding and the digits are noise), then the coarsest grid (largest d:
  // fewest nodes, cheapest for a CNN), then the smallest support h/d.
  auto better = [](const Row& x, const Row& y) {
    const auto key = [](const Row& r) {
      return std::tuple{std::max(r.median, kExact), std::max(r.mean, kExact), -r.s.d, r.s.ratio};
    };
    return key(x) < key(y);
  };
  const Row best = *std::min_element(rows.begin(), rows.end(), better);
  std::ostringstream md;
  md << "# SPH round-trip study\n\n";
  md << "How much of the solved contact forces survives particle → grid → particle (docs/sph.md). "
        "Relative error |λ_rt − λ|₂ / |λ|₂ with λ = (λ_n, λ_t), over contacts with |λ_n| > "
     << a.min_lambda << " N.\n\n";
  md << "Scene: " << (a.scene.file.empty() ? std::string("the seed scene") : "`" + a.scene.file + "`")
     << ", seeds " << a.seeds << ", " << def.time.steps << " steps (sampling every k-th step, k = " << a.every << "), solver `"
     << def.solver.name << "` with " << opt.max_sweeps << " sweeps (built-in warm start); " << frames.size()
     << " frames, " << contacts << " contacts, " << rows.front().contacts << " evaluated per setting. "
     << "Simulation " << num(std::round(sim_seconds * 10) / 10) << " s.\n\n"
     << "Shepard is exact (up to rounding) for every contact whose cell corners are reached by no other "
        "contact's kernel; its error grows with the overlap of supports (large h, coarse d). An exact round "
        "trip is necessary, not sufficient, for a learnable label grid: smoother fields (larger h) may be "
        "easier for a CNN to predict.\n\n";
  md << "## Best setting\n\n";
  md << "**" << to_string(best.s.kernel) << ", d = " << num(best.s.d) << ", h = " << num(best.s.ratio) << "·d = "
     << num(best.s.ratio * best.s.d) << ", " << to_string(best.s.norm) << "**: median error " << pct(best.median)
     << ", 90th percentile " << pct(best.p90) << ", mean " << pct(best.mean) << ", median λ_n retained "
     << num(best.retained_n, 3) << ".\n\n"
     << "Ranking: median error, then mean error, both floored at " << kExact
     << " (below it the round trip is exact up to rounding), then the coarsest grid, then the smallest h/d.\n\n";
  md << "| normalisation | best kernel | d | h/d | median error | p90 | median λ_n retained | unsupported |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const auto norm : norms) {
    const Row* b = nullptr;
    for (const Row& r : rows)
      if (r.s.norm == norm && (!b || better(r, *b))) b = &r;
    if (!b) continue;
    md << "| " << to_string(norm) << " | " << to_string(b->s.kernel) << " | " << num(b->s.d) << " | "
       << num(b->s.ratio) << " | " << pct(b->median) << " | " << pct(b->p90) << " | " << num(b->retained_n, 3)
       << " | " << pct(b->unsupported) << " |\n";
  }
  // The seed's own settings in every mode.
  md << "\n## The seed settings\n\n| setting | normalisation | median error | p90 | mean | median λ_n retained |"
        " unsupported |\n|---|---|---|---|---|---|---|\n";
  for (const auto& [kernel, d] : {std::pair{SphKernelType::Poly6, 0.5}, std::pair{SphKernelType::Spiky, 0.25}})
    for (const Row& r : rows)
      if (r.s.kernel == kernel && r.s.d == d && r.s.ratio == 1.0)
        md << "| " << to_string(kernel) << ", d = h = " << num(d) << " | " << to_string(r.s.norm) << " | "
           << pct(r.median) << " | " << pct(r.p90) << " | " << pct(r.mean) << " | " << num(r.retained_n, 3) << " | "
           << pct(r.unsupported) << " |\n";
  // Legacy loss at the seed setting and over its whole grid.
  double lo = 1e300, hi = -1e300;
  const Row* seed_legacy = nullptr;
  for (const Row& r : rows)
    if (r.s.norm == SphNormalisation::SumToOneLegacy) {
      lo = std::min(lo, r.retained_n);
      hi = std::max(hi, r.retained_n);
      if (r.s.kernel == SphKernelType::Poly6 && r.s.d == 0.5 && r.s.ratio == 1.0) seed_legacy = &r;
    }
  if (hi >= lo) {
    md << "\n## Legacy sum-to-one loss\n\n";
    if (seed_legacy)
      md << "At the seed setting (poly6, d = h = 0.5) the legacy mode returns a median " << num(seed_legacy->retained_n, 3)
         << " of λ_n (median error " << pct(seed_legacy->median) << "). ";
    md << "Over all its settings the median retained λ_n ranges over " << num(lo, 3) << " … " << num(hi, 3) << ".\n";
  }
  md << "\n## Median relative error per setting\n\n"
        "Rows: kernel and spacing d [m]; columns: h/d. h/d ≤ √2/2 ≈ 0.707 leaves points without kernel "
        "support (Shepard returns 0 there: see the unsupported share in the CSV).\n";
  for (const auto norm : norms) {
    md << "\n### " << to_string(norm) << "\n\n| kernel | d |";
    for (const double r : ratios) md << " h/d = " << num(r) << " |";
    md << "\n|---|---|";
    for (std::size_t k = 0; k < ratios.size(); ++k) md << "---|";
    md << '\n';
    for (const auto kernel : kernels)
      for (const double d : spacings) {
        md << "| " << to_string(kernel) << " | " << num(d) << " |";
        for (const double ratio : ratios)
          for (const Row& r : rows)
            if (r.s.norm == norm && r.s.kernel == kernel && r.s.d == d && r.s.ratio == ratio) md << ' ' << pct(r.median) << " |";
        md << '\n';
      }
    md << "\n![" << to_string(norm) << "](sph_study_" << to_string(norm) << ".png)\n";
  }
  write_file(dir / "sph_study.md", md.str());

  // ---- heat maps -----------------------------------------------------------------------
  const std::string script = std::string(DC_SOURCE_DIR) + "/research/plots/sph_study.py";
  const std::string py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string cmd = py + " '" + script + "' '" + (dir / "sph_study.csv").string() + "' '" + dir.string() + "'";
  if (const int rc = std::system(cmd.c_str()); rc != 0)
    std::fprintf(stderr, "deepcontact sph-study: warning: plotting failed (exit %d)\n", rc);

  std::printf("best: %s d=%g h/d=%g %s: median relative error %s (p90 %s)\n", to_string(best.s.kernel), best.s.d,
              best.s.ratio, to_string(best.s.norm), pct(best.median).c_str(), pct(best.p90).c_str());
  if (seed_legacy)
    std::printf("legacy sum-to-one at the seed setting (poly6, d = h = 0.5): median lambda_n retained %.3f\n",
                seed_legacy->retained_n);
  std::printf("report: %s/sph_study.md\n", dir.string().c_str());
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
