#include "dc/engine/world.hpp"

#include <chrono>
#include <cmath>
#include <cstring>

#include "collision/narrow_phase.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/broad_phase.hpp"
#include "lcp/assembly.hpp"
#include "world/restitution.hpp"

namespace dc {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

World::World(WorldDef def) : def_(std::move(def)), inflow_(def_) {
  bodies_ = make_bodies(def_);
  inflow_.emit(0.0, bodies_);
}

World::World(WorldDef def, BodyState bodies)
    : def_(std::move(def)), bodies_(std::move(bodies)), inflow_(def_) {
  def_.validate();
  const std::size_t n = bodies_.size();
  if (bodies_.angle.size() != n || bodies_.velocity.size() != n || bodies_.omega.size() != n ||
      bodies_.radius.size() != n || bodies_.mass.size() != n || bodies_.inv_mass.size() != n ||
      bodies_.inertia.size() != n || bodies_.inv_inertia.size() != n ||
      (!bodies_.shapes.empty() && bodies_.shapes.size() != n))
    throw InvalidArgument("World: body state arrays have inconsistent sizes");
}

const std::vector<Contact>& World::collide() {
  if (contacts_are_previous_) {  // the contacts integrate() solved become previous_contacts()
    previous_.swap(contacts_);
    contacts_are_previous_ = false;
  }
  if (!bodies_.shapes.empty()) {  // shapes or static/kinematic bodies (shape_narrow_phase.hpp)
    shape_narrow_phase_.collide(bodies_, def_, broad_phase_, contacts_);
    if (def_.contact.restitution > 0) track_approach_velocities(bodies_, previous_, contacts_);
    return contacts_;
  }
  const int n = static_cast<int>(bodies_.size());
  const double dt = def_.time.dt;
  contacts_.clear();

  std::vector<double>& spec = spec_;
  spec.resize(static_cast<size_t>(n));
  reach_.resize(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    spec[static_cast<size_t>(k)] = speculative_reach(bodies_, k, def_.contact, dt);
    reach_[static_cast<size_t>(k)] = bodies_.radius[static_cast<size_t>(k)] + spec[static_cast<size_t>(k)];
  }

  // Walls first (their keys sort first), body by body, in wall-id order left..top.
  static constexpr Wall kWalls[4] = {Wall::Left, Wall::Right, Wall::Bottom, Wall::Top};
  for (int w = 3; w >= 0; --w) {  // keys: top (−4) < bottom (−3) < right (−2) < left (−1)
    if (!def_.world.walls[static_cast<size_t>(w)]) continue;
    for (int k = 0; k < n; ++k)
      if (auto c = circle_wall(bodies_, k, kWalls[w], def_.world.width, def_.world.height,
                               2 * spec[static_cast<size_t>(k)]))
        contacts_.push_back(*c);
  }
  const auto t0 = Clock::now();
  broad_phase_.find_pairs(bodies_.position, reach_, pairs_);
  broad_phase_ms_ = ms_since(t0);
  for (const auto& [a, b] : pairs_)
    if (auto c = circle_circle(bodies_, a, b, spec[static_cast<size_t>(a)] + spec[static_cast<size_t>(b)]))
      contacts_.push_back(*c);
  // Wall contacts were appended in key order and pairs are sorted: contacts_ is sorted.
  if (def_.contact.restitution > 0) track_approach_velocities(bodies_, previous_, contacts_);
  return contacts_;
}

const LcpProblem& World::assemble() {
  assemble_lcp(bodies_, contacts_, def_, problem_);
  return problem_;
}

const LcpProblem& World::ensure_assembled_matrix() {
  problem_.ensure_assembled_matrix();
  return problem_;
}

Eigen::VectorXd World::pack(const std::vector<double>& lambda_n,
                            const std::vector<double>& lambda_t) const {
  return problem_.constraints.scatter(lambda_n, lambda_t);
}

void World::predict(const Eigen::VectorXd& lambda, StepOutcome& out) const {
  predict_step(bodies_, contacts_, problem_, def_, lambda, out);
}

void World::integrate(const Eigen::VectorXd& lambda) {
  const int rows = problem_.rows();
  if (lambda.size() != rows)
    throw InvalidArgument("World::integrate: λ has " + std::to_string(lambda.size()) +
                          " entries, the problem has " + std::to_string(rows) + " rows");
  const ContactConstraints& cons = problem_.constraints;
  if (cons.size() != static_cast<int>(contacts_.size()) || cons.rows() != rows)
    throw InvalidArgument("World::integrate: call collide() and assemble() before integrate()");
  Eigen::VectorXd impulse;
  integrate_bodies(problem_, lambda, def_.world.gravity, def_.time.dt, bodies_, impulse);
  for (int c = 0; c < static_cast<int>(contacts_.size()); ++c) {
    contacts_[static_cast<size_t>(c)].lambda_n = cons.lambda_n(lambda, c);
    contacts_[static_cast<size_t>(c)].lambda_t = cons.lambda_t(lambda, c);
  }
  contacts_are_previous_ = true;
  ++step_;
  inflow_.emit(time(), bodies_);
}

StepReport World::step(const LcpSolver& solver, const SolverOptions& options,
                       const InitialGuess& guess) {
  StepReport rep;
  auto t0 = Clock::now();
  collide();
  rep.profile.collide_ms = ms_since(t0);
  rep.profile.broad_phase_ms = broad_phase_ms_;
  t0 = Clock::now();
  assemble();
  if (solver.needs_assembled_matrix()) problem_.ensure_assembled_matrix();
  rep.profile.assemble_ms = ms_since(t0);
  rep.contacts = static_cast<int>(contacts_.size());
  rep.rows = problem_.rows();

  t0 = Clock::now();
  Eigen::VectorXd lambda0 = guess ? guess(*this) : Eigen::VectorXd::Zero(rep.rows);
  rep.profile.warmstart_ms = ms_since(t0);
  if (lambda0.size() != rep.rows)
    throw InvalidArgument("World::step: the initial guess has " + std::to_string(lambda0.size()) +
                          " entries, the problem has " + std::to_string(rep.rows) + " rows");

  t0 = Clock::now();
  rep.solve = solver.solve(problem_, lambda0, options);
  rep.profile.solve_ms = ms_since(t0);
  if (rep.solve.status == SolveStatus::InvalidInput)
    throw InvalidArgument("World::step: the solver rejected the problem: " + rep.solve.message);

  t0 = Clock::now();
  integrate(rep.solve.lambda);
  rep.profile.integrate_ms = ms_since(t0);
  return rep;
}

double World::kinetic_energy() const { return dc::kinetic_energy(bodies_); }

double World::potential_energy() const { return dc::potential_energy(bodies_, def_.world.gravity); }

double World::max_penetration() const {
  double p = 0;
  for (const Contact& c : contacts_) p = std::max(p, -c.gap);
  return p;
}

std::uint64_t state_hash(const BodyState& s) {
  std::uint64_t h = 1469598103934665603ULL;  // FNV-1a offset basis
  auto mix = [&](double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    for (int i = 0; i < 8; ++i) {
      h ^= (bits >> (8 * i)) & 0xffU;
      h *= 1099511628211ULL;  // FNV prime
    }
  };
  for (std::size_t k = 0; k < s.size(); ++k) {
    mix(s.position[k].x); mix(s.position[k].y); mix(s.angle[k]);
    mix(s.velocity[k].x); mix(s.velocity[k].y); mix(s.omega[k]);
  }
  return h;
}

}  // namespace dc
