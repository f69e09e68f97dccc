#include "dc/engine/world.hpp"

#include <chrono>
#include <cmath>
#include <algorithm>
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
  if (has_internal_order()) update_internal_order();
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
  if (has_internal_order()) update_internal_order();
}

void World::update_internal_order() {
  order_.update_from(bodies_, bodies_edited_);
  bodies_edited_ = false;
  if (last_resort_step_ >= 0 && step_ - last_resort_step_ < def_.bodies.resort_every) return;
  double max_radius = 0;
  for (const double r : order_.state().radius) max_radius = std::max(max_radius, r);
  if (max_radius > 0) order_.resort(2 * max_radius);  // the cell of `[bodies] order = "morton"`
  last_resort_step_ = step_;
}

const std::vector<Contact>& World::collide() {
  if (contacts_are_previous_) {  // the contacts integrate() solved become previous_contacts()
    previous_.swap(contacts_);
    contacts_are_previous_ = false;
  }
  if (has_internal_order()) {
    update_internal_order();
    collide_circles(order_.state(), internal_contacts_);
    order_.contacts_to_external(internal_contacts_, static_cast<int>(bodies_.size()), contacts_);
    if (def_.contact.restitution > 0) {  // matched by external key; copied back to the rows
      track_approach_velocities(bodies_, previous_, contacts_);
      for (int c = 0; c < static_cast<int>(contacts_.size()); ++c) {
        Contact& in = internal_contacts_[static_cast<size_t>(order_.internal_contact(c))];
        in.approach_velocity = contacts_[static_cast<size_t>(c)].approach_velocity;
        in.restitution_due = contacts_[static_cast<size_t>(c)].restitution_due;
      }
    }
    return contacts_;
  }
  if (!bodies_.shapes.empty()) {  // shapes or static/kinematic bodies (shape_narrow_phase.hpp)
    shape_narrow_phase_.collide(bodies_, def_, broad_phase_, contacts_);
  } else {
    collide_circles(bodies_, contacts_);
  }
  if (def_.contact.restitution > 0) track_approach_velocities(bodies_, previous_, contacts_);
  return contacts_;
}

void World::collide_circles(const BodyState& bodies, std::vector<Contact>& out) {
  const int n = static_cast<int>(bodies.size());
  const double dt = def_.time.dt;
  out.clear();

  std::vector<double>& spec = spec_;
  spec.resize(static_cast<size_t>(n));
  reach_.resize(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    spec[static_cast<size_t>(k)] = speculative_reach(bodies, k, def_.contact, dt);
    reach_[static_cast<size_t>(k)] = bodies.radius[static_cast<size_t>(k)] + spec[static_cast<size_t>(k)];
  }

  // Walls first (their keys sort first), body by body, in wall-id order left..top.
  static constexpr Wall kWalls[4] = {Wall::Left, Wall::Right, Wall::Bottom, Wall::Top};
  for (int w = 3; w >= 0; --w) {  // keys: top (−4) < bottom (−3) < right (−2) < left (−1)
    if (!def_.world.walls[static_cast<size_t>(w)]) continue;
    for (int k = 0; k < n; ++k)
      if (auto c = circle_wall(bodies, k, kWalls[w], def_.world.width, def_.world.height,
                               2 * spec[static_cast<size_t>(k)]))
        out.push_back(*c);
  }
  const auto t0 = Clock::now();
  broad_phase_.find_pairs(bodies.position, reach_, pairs_);
  broad_phase_ms_ = ms_since(t0);
  for (const auto& [a, b] : pairs_)
    if (auto c = circle_circle(bodies, a, b, spec[static_cast<size_t>(a)] + spec[static_cast<size_t>(b)]))
      out.push_back(*c);
  // Wall contacts were appended in key order and pairs are sorted: `out` is sorted.
}

const LcpProblem& World::assemble() {
  if (!has_internal_order()) {
    assemble_lcp(bodies_, contacts_, def_, problem_);
    return problem_;
  }
  assemble_lcp(order_.state(), internal_contacts_, def_, internal_problem_);
  // The public copy: assembled again from the public contacts and bodies. (A permuted copy of
  // the internal problem was tried and measured slower at 40,000 bodies: it reads each
  // internal row's J, b, bounds and μ from seven arrays at random, where assembly reads two
  // bodies' state per contact.)
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
  if (!has_internal_order()) {
    integrate_solved(lambda);
    return;
  }
  order_.rows_to_internal(cons, internal_problem_.constraints, lambda, internal_lambda_);
  integrate_solved(internal_lambda_);
}

void World::integrate_solved(const Eigen::VectorXd& lambda) {
  const bool internal = has_internal_order();
  const LcpProblem& solved = internal ? internal_problem_ : problem_;
  std::vector<Contact>& contacts = internal ? internal_contacts_ : contacts_;
  const ContactConstraints& cons = solved.constraints;
  Eigen::VectorXd impulse;
  integrate_bodies(solved, lambda, def_.world.gravity, def_.time.dt, working_bodies(), impulse);
  for (int c = 0; c < static_cast<int>(contacts.size()); ++c) {
    contacts[static_cast<size_t>(c)].lambda_n = cons.lambda_n(lambda, c);
    contacts[static_cast<size_t>(c)].lambda_t = cons.lambda_t(lambda, c);
  }
  if (internal) {  // the public copies: bodies by external index, λ by external contact
    order_.gather_kinematics(bodies_);
    for (int c = 0; c < static_cast<int>(contacts_.size()); ++c) {
      const Contact& in = internal_contacts_[static_cast<size_t>(order_.internal_contact(c))];
      contacts_[static_cast<size_t>(c)].lambda_n = in.lambda_n;
      contacts_[static_cast<size_t>(c)].lambda_t = in.lambda_t;
    }
  }
  contacts_are_previous_ = true;
  ++step_;
  inflow_.emit(time(), bodies_);  // appended bodies join the internal order at the next collide()
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
  const bool internal = has_internal_order();
  LcpProblem& solved = internal ? internal_problem_ : problem_;  // rows follow space when internal
  if (solver.needs_assembled_matrix()) solved.ensure_assembled_matrix();
  rep.profile.assemble_ms = ms_since(t0);
  rep.contacts = static_cast<int>(contacts_.size());
  rep.rows = problem_.rows();

  t0 = Clock::now();
  Eigen::VectorXd lambda0 = guess ? guess(*this) : Eigen::VectorXd::Zero(rep.rows);
  if (lambda0.size() != rep.rows)
    throw InvalidArgument("World::step: the initial guess has " + std::to_string(lambda0.size()) +
                          " entries, the problem has " + std::to_string(rep.rows) + " rows");
  if (internal) {
    order_.rows_to_internal(problem_.constraints, solved.constraints, lambda0, internal_lambda_);
    lambda0.swap(internal_lambda_);
  }
  rep.profile.warmstart_ms = ms_since(t0);

  t0 = Clock::now();
  rep.solve = solver.solve(solved, lambda0, options);
  rep.profile.solve_ms = ms_since(t0);
  if (rep.solve.status == SolveStatus::InvalidInput)
    throw InvalidArgument("World::step: the solver rejected the problem: " + rep.solve.message);

  t0 = Clock::now();
  integrate_solved(rep.solve.lambda);
  if (internal) {  // the report's λ in the rows of problem()
    order_.rows_to_external(problem_.constraints, solved.constraints, rep.solve.lambda, internal_lambda_);
    rep.solve.lambda.swap(internal_lambda_);
  }
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
