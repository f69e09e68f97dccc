// SimulationGenerator: simulation i of a data set, a pure function of (params, i).
//
// Per step: collide + assemble (contacts and the LCP are known), build the feature image
// from the bodies as they are BEFORE the solve and this step's contact points/normals,
// solve λ* tightly from the builtin warm start (previous step's λ by key — it only makes the
// tight solve cheaper, the result is the same λ* up to the tolerance), build the label image
// from λ*, and advance the world with λ* (so the trajectory is the oracle's trajectory).
#include <charconv>
#include <cmath>
#include <sstream>

#include "dc/cnn/data_set.hpp"
#include "dc/cnn/data_set_oracle_solver.hpp"
#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

const char* to_string(OracleKind kind) {
  switch (kind) {
    case OracleKind::Pgs: return "pgs";
    case OracleKind::Newton: return "newton";
  }
  return "?";
}

OracleKind parse_oracle_kind(std::string_view text) {
  for (const OracleKind k : {OracleKind::Pgs, OracleKind::Newton})
    if (text == to_string(k)) return k;
  throw ConfigError("oracle method '" + std::string(text) + "': expected pgs or newton");
}

std::string DataSetOracle::describe() const {
  // Shortest round-trip text of the tolerance (e.g. "1e-09"), so equal settings give equal text.
  char buf[64];
  const auto end = std::to_chars(buf, buf + sizeof buf, tolerance).ptr;
  const std::string t(buf, end);
  std::ostringstream s;
  if (method == OracleKind::Pgs)
    s << "pgs theta=" << t << " sweeps=" << sweeps << " warmstart=builtin";
  else
    s << to_string(method) << " tol=" << t << " polish_sweeps=" << sweeps << " warmstart=builtin";
  return s.str();
}

void DataSetOracle::validate() const {
  if (!(tolerance > 0) || !std::isfinite(tolerance))
    throw ConfigError("oracle tolerance (--oracle-tolerance) must be a number > 0");
  if (sweeps < 1) throw ConfigError("oracle sweeps (--oracle-sweeps) must be >= 1");
}

void DataSetParams::validate() const {
  if (count_min < 0 || count_max < count_min)
    throw ConfigError("--count: body count range " + std::to_string(count_min) + ".." +
                      std::to_string(count_max) + " is empty or negative");
  if (count_max > 1000000) throw ConfigError("--count: more than 1000000 bodies");
  scene.validate();
  if (scene.time.steps < 1) throw ConfigError("--steps: need at least 1 step per simulation");
  image.validate();
  if (image.sph.grid.width != scene.world.width || image.sph.grid.height != scene.world.height)
    throw ConfigError("feature image grid box differs from the scene's [world] width/height");
  oracle.validate();
}

WorldDef DataSetParams::simulation_scene(int index) const {
  WorldDef d = scene;
  const std::uint64_t s = seed + static_cast<std::uint64_t>(index);
  // Count ~ U{count_min … count_max} from its own stream seeded like the scene.
  Rng rng(s);
  d.bodies.count = count_min + static_cast<int>(rng.uniform_int(static_cast<std::uint64_t>(count_max - count_min) + 1));
  d.bodies.seed = s;
  return d;
}

SimulationGenerator::SimulationGenerator(DataSetParams params) : params_(std::move(params)) {
  params_.validate();
}

std::optional<SimulationRecord> SimulationGenerator::run(int index, const std::function<bool()>& keep_going) const {
  const WorldDef def = params_.simulation_scene(index);
  World world(def);
  FeatureImageBuilder images(params_.image);
  auto builtin = default_warm_starters().make("builtin");
  const DataSetOracleSolver oracle(params_.oracle);

  SimulationRecord rec;
  rec.index = index;
  rec.seed = def.bodies.seed;
  rec.bodies = static_cast<int>(world.bodies().size());
  const bool varying = world.inflow().pending();  // bodies enter during the run: per-sample counts
  std::vector<double> lambda_nt;
  for (int s = 0; s < def.time.steps; ++s) {
    if (keep_going && !keep_going()) return std::nullopt;
    world.collide();
    const LcpProblem& problem = world.assemble();
    const std::vector<Contact>& contacts = world.contacts();
    if (contacts.empty()) {
      world.integrate(Eigen::VectorXd::Zero(0));
      continue;
    }
    // Features first: they must only see what a predictor sees before the solve.
    const std::size_t f0 = rec.features.size();
    rec.features.resize(f0 + images.feature_size());
    images.features(world.bodies(), contacts, world.previous_contacts(), &problem,
                    std::span<float>(rec.features).subspan(f0));

    const Eigen::VectorXd guess = builtin->initial_guess(StepView{world, nullptr});
    auto [lambda, residual] = oracle.solve(problem, guess);
    if (!lambda.allFinite())
      throw std::runtime_error("simulation " + std::to_string(index) + " (seed " + std::to_string(rec.seed) +
                               "), step " + std::to_string(s) + ": the oracle returned a non-finite lambda");
    if (!(residual <= rec.max_residual)) rec.max_residual = residual;

    world.constraints().gather(lambda, lambda_nt);  // (λ_n, λ_t) per contact
    const std::size_t l0 = rec.labels.size();
    rec.labels.resize(l0 + images.label_size());
    images.labels(contacts, lambda_nt, std::span<float>(rec.labels).subspan(l0));

    rec.step.push_back(s);
    rec.contact_count.push_back(static_cast<std::int32_t>(contacts.size()));
    rec.residual.push_back(residual);
    const BodyState& b = world.bodies();
    const std::size_t B = b.size();
    if (varying) rec.body_count.push_back(static_cast<std::int32_t>(B));
    rec.bodies = static_cast<int>(B);
    for (std::size_t k = 0; k < B; ++k) {
      rec.position.insert(rec.position.end(), {b.position[k].x, b.position[k].y});
      rec.velocity.insert(rec.velocity.end(), {b.velocity[k].x, b.velocity[k].y});
      rec.omega.push_back(b.omega[k]);
      rec.angle.push_back(b.angle[k]);
      rec.radius.push_back(b.radius[k]);
      rec.mass.push_back(b.mass[k]);
    }
    for (std::size_t c = 0; c < contacts.size(); ++c) {
      const Contact& k = contacts[c];
      rec.body_a.push_back(k.body_a);
      rec.body_b.push_back(k.body_b);
      rec.point.insert(rec.point.end(), {k.point.x, k.point.y});
      rec.normal.insert(rec.normal.end(), {k.normal.x, k.normal.y});
      rec.gap.push_back(k.gap);
      rec.lambda_star.insert(rec.lambda_star.end(), {lambda_nt[2 * c], lambda_nt[2 * c + 1]});
    }
    world.integrate(lambda);
  }
  return rec;
}

}  // namespace dc
