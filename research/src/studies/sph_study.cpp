// The measurement of the SPH round-trip study (sph_study.hpp): simulate, then round-trip every
// sampled step through every setting.
#include "dc/research/sph_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "dc/bench/quantiles.hpp"
#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"

namespace dc {

void SphStudyDef::validate() const {
  if (steps < 0) throw ConfigError("--steps must be >= 0");
  if (every < 1) throw ConfigError("--every must be >= 1");
  if (sweeps < 0) throw ConfigError("--sweeps must be >= 0");
  if (!(min_lambda >= 0) || !std::isfinite(min_lambda)) throw ConfigError("--min-lambda must be finite and >= 0");
  if (seeds.empty()) throw ConfigError("--seeds: give at least one seed");
  if (kernels.empty()) throw ConfigError("--kernels: give at least one kernel");
  if (normalisations.empty()) throw ConfigError("--normalisations: give at least one mode");
  if (spacings.empty()) throw ConfigError("--spacings: give at least one spacing");
  if (ratios.empty()) throw ConfigError("--ratios: give at least one ratio");
  for (const double d : spacings)
    if (!(d > 0) || !std::isfinite(d)) throw ConfigError("--spacings: every spacing must be a positive number");
  for (const double r : ratios)
    if (!(r > 0) || !std::isfinite(r)) throw ConfigError("--ratios: every ratio must be a positive number");
}

namespace {

/// One step's contacts: points and particle-major (λ_n, λ_t).
struct Frame {
  std::vector<Vec2> points;
  std::vector<double> lambda;
};

/// Built-in warm start (previous λ by contact key): the study needs well-converged λ, not a
/// solver benchmark, and this converges the fixed sweep budget furthest.
Eigen::VectorXd previous_lambda(const World& w) {
  std::unordered_map<ContactKey, std::pair<double, double>, ContactKeyHash> prev;
  for (const Contact& c : w.previous_contacts()) prev[c.key] = {c.lambda_n, c.lambda_t};
  std::vector<double> ln(w.contacts().size(), 0.0), lt(w.contacts().size(), 0.0);
  for (std::size_t c = 0; c < w.contacts().size(); ++c)
    if (const auto it = prev.find(w.contacts()[c].key); it != prev.end()) {
      ln[c] = it->second.first;
      lt[c] = it->second.second;
    }
  return w.pack(ln, lt);
}

/// Simulates one seed; returns the sampled frames (steps with at least one contact).
std::vector<Frame> simulate(WorldDef def, LcpSolver& solver, const SolverOptions& opt, int every) {
  World world(std::move(def));
  std::vector<Frame> frames;
  const int steps = world.def().time.steps;
  for (int s = 0; s < steps; ++s) {
    world.step(solver, opt, previous_lambda);
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

/// The per-contact errors of one setting, reused across settings to avoid reallocating.
struct ErrorBuffers {
  std::vector<double> err, err_n, kept;
};

SphStudyRow evaluate(const SphStudySetting& s, const WorldDef& def, const std::vector<Frame>& frames,
                     double min_lambda, ErrorBuffers& b) {
  SphTransferDef td;
  td.grid = SphGridDef{def.world.width, def.world.height, s.d, 2};
  td.kernel = s.kernel;
  td.support = s.ratio * s.d;
  td.normalisation = s.normalisation;
  SphTransfer t(td);
  b.err.clear();
  b.err_n.clear();
  b.kept.clear();
  std::size_t flagged = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (const Frame& f : frames) {
    const auto rt = t.round_trip(f.points, f.lambda);
    const auto flags = t.unsupported();
    for (std::size_t c = 0; c < f.points.size(); ++c) {
      const double ln = f.lambda[2 * c], lt = f.lambda[2 * c + 1];
      if (!(std::abs(ln) > min_lambda)) continue;
      const double en = rt[2 * c] - ln, et = rt[2 * c + 1] - lt;
      b.err.push_back(std::hypot(en, et) / std::hypot(ln, lt));
      b.err_n.push_back(std::abs(en) / std::abs(ln));
      b.kept.push_back(rt[2 * c] / ln);
      flagged += flags[c];
    }
  }
  SphStudyRow r;
  r.s = s;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.contacts = b.err.size();
  double sum = 0;
  for (const double e : b.err) sum += e;
  r.mean = b.err.empty() ? std::numeric_limits<double>::quiet_NaN() : sum / b.err.size();
  r.median = bench::quantile(b.err, 0.5);  // NaN when there are no values
  r.p90 = bench::quantile(b.err, 0.9);
  r.median_n = bench::quantile(b.err_n, 0.5);
  r.retained_n = bench::quantile(b.kept, 0.5);
  r.unsupported = b.err.empty() ? 0.0 : static_cast<double>(flagged) / b.err.size();
  return r;
}

}  // namespace

SphStudyResults run_sph_study(const WorldDef& scene, const SphStudyDef& def, const SphStudySeedHook& on_seed) {
  def.validate();
  SphStudyResults out;
  out.def = def;
  WorldDef world = scene;
  if (def.steps > 0) world.time.steps = def.steps;
  // Validate every grid before the (long) simulation.
  for (const double d : def.spacings) SphGridDef{world.world.width, world.world.height, d, 2}.validate();

  const auto solver = make_solver(world.solver.name);
  SolverOptions opt = solver_options(world.solver);
  if (def.sweeps > 0) opt.max_sweeps = def.sweeps;
  opt.record_theta = false;
  out.steps = world.time.steps;
  out.solver = to_string(world.solver.name);
  out.sweeps = opt.max_sweeps;

  const auto t_sim = std::chrono::steady_clock::now();
  std::vector<Frame> frames;
  for (const auto seed : def.seeds) {
    WorldDef d = world;
    d.bodies.seed = seed;
    auto f = simulate(d, *solver, opt, def.every);
    std::size_t nc = 0;
    for (const auto& fr : f) nc += fr.points.size();
    if (on_seed) on_seed(seed, f.size(), nc);
    out.contacts += nc;
    for (auto& fr : f) frames.push_back(std::move(fr));
  }
  out.simulation_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_sim).count();
  out.frames = frames.size();
  if (frames.empty()) throw ConfigError("sph-study: the simulation produced no contacts (nothing to study)");

  ErrorBuffers buffers;
  for (const auto norm : def.normalisations)
    for (const auto kernel : def.kernels)
      for (const double d : def.spacings)
        for (const double ratio : def.ratios)
          out.rows.push_back(evaluate(SphStudySetting{kernel, d, ratio, norm}, world, frames, def.min_lambda, buffers));
  if (out.rows.front().contacts == 0) throw ConfigError("sph-study: no contact has |lambda_n| > --min-lambda");
  return out;
}

bool sph_study_ranks_before(const SphStudyRow& a, const SphStudyRow& b) {
  const auto key = [](const SphStudyRow& r) {
    return std::tuple{std::max(r.median, kSphStudyExact), std::max(r.mean, kSphStudyExact), -r.s.d, r.s.ratio};
  };
  return key(a) < key(b);
}

const SphStudyRow& best_sph_study_row(const SphStudyResults& r) {
  if (r.rows.empty()) throw InvalidArgument("best_sph_study_row: the study has no rows");
  return *std::min_element(r.rows.begin(), r.rows.end(), sph_study_ranks_before);
}

const SphStudyRow* legacy_seed_row(const SphStudyResults& r) {
  const SphStudyRow* found = nullptr;  // the last one, should a list name a value twice
  for (const SphStudyRow& row : r.rows)
    if (row.s.normalisation == SphNormalisation::SumToOneLegacy && row.s.kernel == SphKernelType::Poly6 &&
        row.s.d == 0.5 && row.s.ratio == 1.0)
      found = &row;
  return found;
}

}  // namespace dc
