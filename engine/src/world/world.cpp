#include "dc/engine/world.hpp"

#include <chrono>
#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <utility>

#include "collision/narrow_phase.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/broad_phase.hpp"
#include "dc/engine/contact_match.hpp"
#include "dc/engine/matched_lambda.hpp"
#include "assembly/assembly.hpp"
#include "world/parts/contact_lambdas.hpp"
#include "world/parts/integrate_keeping.hpp"
#include "world/parts/relax_pass.hpp"
#include "world/internal_order_choice.hpp"
#include "world/restitution.hpp"
#include "world/parts/step_parts.hpp"
#include "world/parts/warm_start_parts.hpp"

namespace dc {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// Empties a job's contact list for refilling, first making room when it holds less than 1/8
/// (+ 16) above its last size: a list copied with a World holds only its contacts, and a job's
/// count moves a little from step to step, so without headroom it would reallocate on the steps
/// it grows. Room for 3/2 of the last size + 64 then keeps the growths geometric.
void clear_with_headroom(std::vector<Contact>& list) {
  const std::size_t n = list.size();
  list.clear();
  if (list.capacity() < n + n / 8 + 16) list.reserve(n + n / 2 + 64);
}

}  // namespace

World::World(WorldDef def) : def_(std::move(def)), inflow_(def_) {
  bodies_ = make_bodies(def_);
  inflow_.emit(0.0, bodies_);
  internal_ = steps_in_internal_order(def_.bodies.internal_order, bodies_);
  if (internal_) update_internal_order();
}

World::World(WorldDef def, BodyState bodies)
    : def_(std::move(def)), bodies_(std::move(bodies)), inflow_(def_) {
  def_.validate();
  internal_ = steps_in_internal_order(def_.bodies.internal_order, bodies_);
  const std::size_t n = bodies_.size();
  if (bodies_.angle.size() != n || bodies_.velocity.size() != n || bodies_.omega.size() != n ||
      bodies_.radius.size() != n || bodies_.mass.size() != n || bodies_.inv_mass.size() != n ||
      bodies_.inertia.size() != n || bodies_.inv_inertia.size() != n ||
      (!bodies_.shapes.empty() && bodies_.shapes.size() != n))
    throw InvalidArgument("World: body state arrays have inconsistent sizes");
  if (internal_) update_internal_order();
}

void World::update_internal_order() {
  // Edited bodies are copied whole: bring the public copy up to date first (gathered after the
  // last integrate() unless read since), so that only the user's edits change the state.
  if (bodies_edited_ && bodies_stale_) gather_bodies();
  order_.update_from(bodies_, bodies_edited_);
  bodies_edited_ = false;
  const bool due = last_resort_step_ < 0 || decayed_ || step_ - last_resort_step_ >= def_.bodies.resort_every;
  if (!due) return;
  double max_radius = 0;
  for (const double r : order_.state().radius) max_radius = std::max(max_radius, r);
  if (max_radius > 0) {
    order_.resort(2 * max_radius);  // the cell of `[bodies] order = "morton"`
    order_.rekey(internal_previous_);  // the builtin warm start matches by the new internal keys
    order_stale_ = true;
  }
  last_resort_step_ = step_;
  ++resorts_;
  decayed_ = false;
  spread_baseline_due_ = true;
}

void World::gather_bodies() const {
  order_.gather_kinematics(bodies_);
  bodies_stale_ = false;
}

const std::vector<int>& World::public_order() const {
  if (order_stale_) {
    const int n = static_cast<int>(order_.external_of().size());
    if (internal_assembled_)  // the keys from the constraints: a smaller stream than the contacts
      order_.external_order(internal_contacts_, internal_problem_.constraints, n, internal_of_contact_);
    else
      order_.external_order(internal_contacts_, n, internal_of_contact_);
    order_stale_ = false;
  }
  return internal_of_contact_;
}

const std::vector<Contact>& World::contacts() const {
  if (contacts_stale_) {
    order_.contacts_to_external(internal_contacts_, public_order(), contacts_);
    contacts_stale_ = false;
  }
  if (lambdas_unstored_) {
    store_contact_lambdas(lambdas_, contacts_);
    lambdas_unstored_ = false;
  }
  return contacts_;
}

const std::vector<Contact>& World::previous_contacts() const {
  if (contacts_are_previous_) return contacts();
  if (previous_stale_) {  // keyed in the current internal order (rekey at a re-sort)
    std::vector<int> internal_of;
    order_.external_order(internal_previous_, static_cast<int>(order_.external_of().size()), internal_of);
    order_.contacts_to_external(internal_previous_, internal_of, previous_);
    previous_stale_ = false;
  }
  if (previous_lambdas_unstored_) {
    store_contact_lambdas(previous_lambdas_, previous_);
    previous_lambdas_unstored_ = false;
  }
  return previous_;
}

const LcpProblem& World::problem() const {
  if (problem_stale_) {  // the public contacts assembled on the bodies as they were at assemble()
    const BodyState& s = order_.state();
    if (contacts_are_previous_)
      order_.bodies_for_assembly(pre_position_, pre_velocity_, pre_omega_, assembly_bodies_);
    else
      order_.bodies_for_assembly(s.position, s.velocity, s.omega, assembly_bodies_);
    assemble_lcp(assembly_bodies_, contacts(), def_, problem_);
    problem_stale_ = false;
  }
  return problem_;
}

void World::builtin_guess_into(KeptVector& out) const {
  const std::vector<Contact>& prev = contacts_are_previous_ ? contacts_ : previous_;
  const std::vector<ContactLambda>& packed = contacts_are_previous_ ? lambdas_ : previous_lambdas_;
  if (internal_ || packed.size() != prev.size())
    return put_matched_lambda(previous_contacts(), contacts(), problem(), out);
  put_matched_lambda(prev, packed, contacts_, problem_, out);  // contacts_ and problem_ are the public ones
}

const std::vector<Contact>& World::collide() {
  collide_stage();
  return contacts();
}

void World::collide_stage() {
  if (contacts_are_previous_) {  // the contacts integrate() solved become previous_contacts()
    if (internal_) {
      internal_previous_.swap(internal_contacts_);
      if (!contacts_stale_) previous_.swap(contacts_);
      previous_stale_ = contacts_stale_;
    } else {
      previous_.swap(contacts_);
      previous_lambdas_.swap(lambdas_);
      previous_lambdas_unstored_ = std::exchange(lambdas_unstored_, false);  // contacts_ is refilled below
    }
    contacts_are_previous_ = false;
  }
  if (internal_) {
    update_internal_order();
    internal_assembled_ = false;
    collide_circles(order_.state(), internal_contacts_);
    contacts_stale_ = problem_stale_ = order_stale_ = true;
    // Decay: the mean |i − j| of the pairs in contact against its lowest value since the last
    // re-sort (the order's best; a cloud that settles into a pile lowers it after the sort).
    // Means compared as Σ₁·n₀ > D·Σ₀·n₁ (integers converted exactly below 2⁵³).
    const auto& best = spread_at_resort_;
    const auto below = [](const InternalBodyOrder::Spread& x, const InternalBodyOrder::Spread& y, double factor) {
      return static_cast<double>(x.sum) * static_cast<double>(y.pairs) <
             factor * static_cast<double>(y.sum) * static_cast<double>(x.pairs);
    };
    if (spread_.pairs > 0) {
      if (spread_baseline_due_ || best.pairs == 0 || below(spread_, best, 1.0)) {
        spread_at_resort_ = spread_;
        spread_baseline_due_ = false;
      } else {
        decayed_ = !below(spread_, best, def_.bodies.resort_decay);
      }
    }
    if (def_.contact.restitution > 0) {  // matched by external key; copied back to the rows
      (void)contacts();  // builds contacts_, which track_approach_velocities completes
      track_approach_velocities(std::as_const(*this).bodies(), previous_contacts(), contacts_);
      const std::vector<int>& internal_of = public_order();
      for (std::size_t c = 0; c < contacts_.size(); ++c) {
        Contact& in = internal_contacts_[static_cast<size_t>(internal_of[c])];
        in.approach_velocity = contacts_[c].approach_velocity;
        in.restitution_due = contacts_[c].restitution_due;
      }
    }
    return;
  }
  if (!bodies_.shapes.empty()) {  // shapes or static/kinematic bodies (shape_narrow_phase.hpp)
    shape_narrow_phase_.collide(bodies_, def_, broad_phase_, contacts_);
  } else {
    collide_circles(bodies_, contacts_);
  }
  if (def_.contact.restitution > 0) track_approach_velocities(bodies_, previous_contacts(), contacts_);
}

void World::collide_circles(const BodyState& bodies, std::vector<Contact>& out) {
  const int n = static_cast<int>(bodies.size());
  const double dt = def_.time.dt;
  const int threads = step_threads_;

  // Per job of bodies: the packed records the narrow phase reads (circle_probe.hpp) and the
  // reaches, then its wall contacts, wall by wall. Walls first (their keys sort first), body by
  // body, in wall-id order left..top: keys top (−4) < bottom (−3) < right (−2) < left (−1), so the
  // jobs' lists are merged wall by wall, each in job order.
  static constexpr Wall kWalls[4] = {Wall::Left, Wall::Right, Wall::Bottom, Wall::Top};
  probes_.resize(static_cast<size_t>(n));
  reach_.resize(static_cast<size_t>(n));
  const int body_jobs = parts_for(threads, n, 2, 1024);
  // With jobs of bodies `out` is resized (not cleared) once the counts are known: its elements
  // are all overwritten, and only the growth is built.
  if (body_jobs == 1) out.clear();
  if (part_walls_.size() < static_cast<size_t>(4 * body_jobs)) part_walls_.resize(static_cast<size_t>(4 * body_jobs));
  run_parts(threads, body_jobs, [&](int p) {
    const int lo = static_cast<int>(part_begin(n, body_jobs, p));
    const int hi = static_cast<int>(part_begin(n, body_jobs, p + 1));
    for (int k = lo; k < hi; ++k) {
      const auto i = static_cast<size_t>(k);
      const double spec = speculative_reach(bodies, k, def_.contact, dt);
      probes_[i] = CircleProbe{bodies.position[i], bodies.radius[i], spec};
      reach_[i] = bodies.radius[i] + spec;
    }
    for (int w = 3; w >= 0; --w) {
      std::vector<Contact>& list = body_jobs == 1 ? out : part_walls_[static_cast<size_t>(4 * p + w)];
      if (body_jobs > 1) clear_with_headroom(list);
      if (!def_.world.walls[static_cast<size_t>(w)]) continue;
      add_wall_contacts(probes_.data(), lo, hi, kWalls[w], def_.world.width, def_.world.height, list);
    }
  });
  const auto t0 = Clock::now();
  const std::vector<std::pair<int, int>>& pairs = pair_cache_.pairs(bodies.position, reach_, broad_phase_, threads);
  broad_phase_ms_ = ms_since(t0);
  // The pair contacts and their spread (integers: any order sums alike).
  const long np = static_cast<long>(pairs.size());
  spread_ = {};
  if (body_jobs == 1 && parts_for(threads, np, 4, 1024) == 1) {  // one thread: appended in place
    add_pair_contacts(probes_.data(), pairs.data(), 0, np, out, spread_.sum, spread_.pairs);
  } else {
    place_pair_contacts(threads, body_jobs, pairs, out);
  }
  // Wall contacts come in key order and pairs are sorted: `out` is sorted.
}

void World::place_pair_contacts(int threads, int body_jobs, const std::vector<std::pair<int, int>>& pairs,
                                std::vector<Contact>& out) {
  // Counts first (the reach test alone), then offsets, then each job writes its contacts into
  // out[at[p], at[p + 1]): the same array as lists appended in job order, without the lists'
  // writes and their copy. The offsets and spreads are kept members: no allocation once they
  // hold the most jobs.
  const long np = static_cast<long>(pairs.size());
  const int jobs = parts_for(threads, np, 4, 1024);
  std::vector<std::size_t>& at = pair_at_;
  at.assign(static_cast<size_t>(jobs) + 1, 0);
  run_parts(threads, jobs, [&](int p) {
    at[static_cast<size_t>(p) + 1] = static_cast<std::size_t>(
        count_pair_contacts(probes_.data(), pairs.data(), part_begin(np, jobs, p), part_begin(np, jobs, p + 1)));
  });
  // The wall contacts first: already in `out` from one job of bodies, else the jobs' lists wall
  // by wall (top..left), each in job order.
  std::size_t walls = 0;
  if (body_jobs == 1) {
    walls = out.size();
  } else {
    for (int p = 0; p < 4 * body_jobs; ++p) walls += part_walls_[static_cast<size_t>(p)].size();
  }
  at[0] = walls;
  for (int p = 0; p < jobs; ++p) at[static_cast<size_t>(p) + 1] += at[static_cast<size_t>(p)];
  // Room to grow (resize of an empty vector would allocate the count exactly, again at each
  // step the contacts grow): the serial path's push_back grows geometrically alike.
  if (out.capacity() < at.back()) out.reserve(at.back() + at.back() / 2);
  out.resize(at.back());
  if (body_jobs > 1) {
    auto to = out.begin();
    for (int w = 3; w >= 0; --w)
      for (int p = 0; p < body_jobs; ++p) {
        const std::vector<Contact>& list = part_walls_[static_cast<size_t>(4 * p + w)];
        to = std::copy(list.begin(), list.end(), to);
      }
  }
  part_spread_.assign(static_cast<size_t>(jobs), InternalBodyOrder::Spread{});
  run_parts(threads, jobs, [&](int p) {
    InternalBodyOrder::Spread& spread = part_spread_[static_cast<size_t>(p)];
    write_pair_contacts(probes_.data(), pairs.data(), part_begin(np, jobs, p), part_begin(np, jobs, p + 1),
                        out.data() + at[static_cast<size_t>(p)], spread.sum, spread.pairs);
  });
  for (const auto& sp : part_spread_) {
    spread_.sum += sp.sum;
    spread_.pairs += sp.pairs;
  }
}

const LcpProblem& World::assemble() {
  assemble_stage();
  return problem();
}

void World::assemble_stage() {
  if (!internal_) {
    assemble_lcp(bodies_, contacts_, def_, problem_, step_threads_);
    return;
  }
  // The public problem() is assembled on first read (a second assembly, of the public contacts).
  assemble_lcp(order_.state(), internal_contacts_, def_, internal_problem_, step_threads_);
  problem_stale_ = true;
  internal_assembled_ = true;
}

const LcpProblem& World::ensure_assembled_matrix() {
  const LcpProblem& p = problem();  // the public problem exists from here on
  (void)p;
  problem_.ensure_assembled_matrix();
  return problem_;
}

Eigen::VectorXd World::pack(const std::vector<double>& lambda_n,
                            const std::vector<double>& lambda_t) const {
  return problem().constraints.scatter(lambda_n, lambda_t);
}

void World::predict(const Eigen::VectorXd& lambda, StepOutcome& out) const {
  predict_step(bodies(), contacts(), problem(), def_, lambda, out);
}

void World::integrate(const Eigen::Ref<const Eigen::VectorXd>& lambda) {
  const LcpProblem& solved = internal_ ? internal_problem_ : problem_;
  const int rows = solved.rows();
  if (lambda.size() != rows)
    throw InvalidArgument("World::integrate: λ has " + std::to_string(lambda.size()) +
                          " entries, the problem has " + std::to_string(rows) + " rows");
  const std::size_t contacts = internal_ ? internal_contacts_.size() : contacts_.size();
  if (solved.constraints.size() != static_cast<int>(contacts) || solved.constraints.rows() != rows)
    throw InvalidArgument("World::integrate: call collide() and assemble() before integrate()");
  if (!internal_) {
    integrate_solved(lambda);
    return;
  }
  InternalBodyOrder::rows_to_internal(problem().constraints, solved.constraints, public_order(), lambda,
                                      internal_lambda_);
  integrate_solved(internal_lambda_);
}

void World::integrate_solved(const Eigen::Ref<const Eigen::VectorXd>& lambda, const Eigen::VectorXd* position_lambda) {
  const LcpProblem& solved = internal_ ? internal_problem_ : problem_;
  std::vector<Contact>& contacts = internal_ ? internal_contacts_ : contacts_;
  const ContactConstraints& cons = solved.constraints;
  Eigen::VectorXd& impulse = impulse_;
  if (internal_ && problem_stale_)  // keeps what a later first read of problem() assembles on
    integrate_bodies_keeping(solved, lambda, def_.world.gravity, def_.time.dt, working_bodies(), impulse,
                             pre_position_, pre_velocity_, pre_omega_, step_threads_);
  else
    integrate_bodies_on(solved, lambda, def_.world.gravity, def_.time.dt, working_bodies(), impulse, step_threads_);
  if (position_lambda != nullptr)
    shift_positions(solved, *position_lambda, lambda, def_.time.dt, working_bodies(), relax_dl_, impulse);
  if (internal_) {
    const int nc = static_cast<int>(contacts.size());
    const int jobs = parts_for(step_threads_, nc, 2, 4096);
    run_parts(step_threads_, jobs, [&](int p) {
      for (int c = static_cast<int>(part_begin(nc, jobs, p)); c < part_begin(nc, jobs, p + 1); ++c) {
        contacts[static_cast<size_t>(c)].lambda_n = cons.lambda_n(lambda, c);
        contacts[static_cast<size_t>(c)].lambda_t = cons.lambda_t(lambda, c);
      }
    });
  } else {  // packed (contact_lambdas.hpp): written into contacts_ when a caller reads them
    gather_contact_lambdas(cons, lambda, lambdas_);
    lambdas_unstored_ = true;
  }
  if (internal_) bodies_stale_ = contacts_stale_ = true;  // the public views: rebuilt on first read
  contacts_are_previous_ = true;
  ++step_;
  // Appended bodies join the internal order at the next collide(); the inflow's overlap test
  // reads the public bodies, so they are brought up to date first when it may emit.
  if (internal_ && inflow_.pending()) (void)bodies();
  inflow_.emit(time(), bodies_);
}

StepReport World::step(LcpSolver& solver, const SolverOptions& options, const InitialGuess& guess) {
  return step_with(solver, options, &guess);  // an empty function: zeros
}

StepReport World::step(LcpSolver& solver, const SolverOptions& options, WarmStart guess) {
  (void)guess;  // the one engine warm start
  return step_with(solver, options, nullptr);
}

StepReport World::step_with(LcpSolver& solver, const SolverOptions& options, const InitialGuess* guess) {
  // The step's threads: the solver's, for piles large enough and while whole steps pay (their
  // wall time per unit of work, threaded against serial steps) or always when the solver's
  // threads are forced. This pacer alone judges a paced step: the solver is led (its set-up and
  // sweeps on the threads of a threaded step, on one thread in a serial step), since a solve
  // paced on its own probes the threads with a serial set-up, which on a pile the size of a
  // step's may never pay, and would then keep the whole step serial.
  const int requested = solver.thread_capacity();
  const long bodies = static_cast<long>(working_bodies().size());
  const bool large = requested > 1 && bodies >= kMinBodiesPerThread * requested;
  const bool paced = large && !solver.threads_forced();
  // The solver's step pacer where it keeps one (LcpSolver::step_pacer: its verdict outlives
  // this World), else this World's.
  ThreadPacer* kept = paced ? solver.step_pacer(kStepPays) : nullptr;
  ThreadPacer& pacer = kept != nullptr ? *kept : pacer_;
  step_threads_ = large && (!paced || pacer.threaded_next()) ? requested : 1;
  if (paced) {
    solver.lead_threads(true);
    solver.hold_threads(step_threads_ == 1);
  }
  struct Serial {  // after step(), also after a throw: the stages called one by one run
    int& threads;  // serially and the solver chooses its threads again
    LcpSolver& solver;
    bool paced;
    ~Serial() {
      threads = 1;
      if (!paced) return;
      solver.hold_threads(false);
      solver.lead_threads(false);
    }
  } serial_after{step_threads_, solver, paced};
  StepReport rep = step_stages(solver, options, guess);
  if (paced) {
    const double work = static_cast<double>(bodies) + static_cast<double>(rep.rows) * (rep.solve.sweeps + 2);
    pacer.record(step_threads_ > 1, 1e-3 * rep.profile.total_ms(), work);
  }
  return rep;
}

StepReport World::step_stages(LcpSolver& solver, const SolverOptions& options, const InitialGuess* guess) {
  StepReport rep;
  auto t0 = Clock::now();
  collide_stage();
  rep.profile.collide_ms = ms_since(t0);
  rep.profile.broad_phase_ms = broad_phase_ms_;
  t0 = Clock::now();
  assemble_stage();
  LcpProblem& solved = internal_ ? internal_problem_ : problem_;  // rows follow space when internal
  if (solver.needs_assembled_matrix()) solved.ensure_assembled_matrix();
  rep.profile.assemble_ms = ms_since(t0);
  rep.contacts = static_cast<int>(internal_ ? internal_contacts_.size() : contacts_.size());
  rep.rows = solved.rows();

  t0 = Clock::now();
  KeptVector& lambda0 = lambda0_;
  if (guess == nullptr) {
    // The builtin warm start on one set of objects (public, or internal: the same numbers per contact).
    if (internal_)
      previous_lambda(internal_previous_, {}, internal_contacts_, internal_problem_, step_threads_, lambda0, warm_starts_);
    else if (previous_lambdas_.size() == previous_.size())  // previous_ as integrate() left it
      previous_lambda(previous_, previous_lambdas_, contacts_, problem_, step_threads_, lambda0, warm_starts_);
    else
      previous_lambda(previous_contacts(), {}, contacts_, problem_, step_threads_, lambda0, warm_starts_);
  } else {
    lambda0 = *guess ? (*guess)(*this) : Eigen::VectorXd::Zero(rep.rows);
    if (lambda0.size() != rep.rows)
      throw InvalidArgument("World::step: the initial guess has " + std::to_string(lambda0.size()) +
                            " entries, the problem has " + std::to_string(rep.rows) + " rows");
    if (internal_ && *guess) {
      InternalBodyOrder::rows_to_internal(problem().constraints, solved.constraints, public_order(), lambda0,
                                          internal_lambda_);
      lambda0 = internal_lambda_;
    }
  }
  rep.profile.warmstart_ms = ms_since(t0);

  t0 = Clock::now();
  // λ into kept storage (no allocation in the solve while the rows fit it); the report's λ is
  // its own vector (one allocation a step: the report leaves with the caller).
  solver.solve_into(solved, lambda0, options, solved_lambda_, rep.solve);
  rep.profile.solve_ms = ms_since(t0);
  if (rep.solve.status == SolveStatus::InvalidInput)
    throw InvalidArgument("World::step: the solver rejected the problem: " + rep.solve.message);

  t0 = Clock::now();
  if (def_.solver.relax_sweeps > 0 && rep.rows > 0) {
    rep.solve.lambda = Eigen::VectorXd(solved_lambda_);
    relax_solve(solver, options, solved, rep);
    if (internal_) {  // the report's λ in the rows of problem() (external contact order)
      InternalBodyOrder::rows_to_external(solved.constraints, public_order(), rep.solve.lambda, internal_lambda_);
      rep.solve.lambda.swap(internal_lambda_);
    }
  } else {
    integrate_solved(solved_lambda_);
    if (internal_)  // the report's λ in the rows of problem() (external contact order)
      InternalBodyOrder::rows_to_external(solved.constraints, public_order(), solved_lambda_, rep.solve.lambda);
    else
      rep.solve.lambda = Eigen::VectorXd(solved_lambda_);
  }
  rep.profile.integrate_ms = ms_since(t0);
  return rep;
}

void World::relax_solve(LcpSolver& solver, const SolverOptions& options, LcpProblem& solved, StepReport& rep) {
  // b without the bias for the relax sweeps, then back (problem() and the bench read it).
  relax_b_ = solved.b;
  remove_position_bias(internal_ ? internal_contacts_ : contacts_, solved.constraints, def_.contact, def_.time.dt,
                       solved.b);
  SolverOptions ro = options;
  ro.max_sweeps = def_.solver.relax_sweeps;
  ro.checkpoints.clear();
  ro.on_checkpoint = nullptr;
  SolveResult relaxed = solver.solve(solved, rep.solve.lambda, ro);
  solved.b.swap(relax_b_);
  if (relaxed.status == SolveStatus::InvalidInput)
    throw InvalidArgument("World::step: the solver rejected the relax pass: " + relaxed.message);
  relax_lambda_.swap(rep.solve.lambda);  // λ_b: the positions
  rep.solve.lambda = std::move(relaxed.lambda);
  rep.solve.sweeps += relaxed.sweeps;
  rep.solve.residual = relaxed.residual;
  integrate_solved(rep.solve.lambda, &relax_lambda_);
}

double World::kinetic_energy() const { return dc::kinetic_energy(bodies()); }

double World::potential_energy() const { return dc::potential_energy(bodies(), def_.world.gravity); }

double World::max_penetration() const {
  double p = 0;  // a maximum: the same in either contact order
  for (const Contact& c : internal_ ? internal_contacts_ : contacts_) p = std::max(p, -c.gap);
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
