#include "dc/bench/stress_scenarios.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "dc/core/error.hpp"
#include "dc/engine/broad_phase.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/engine/shape_narrow_phase.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc::stress {
namespace {

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

}  // namespace

// ---- measurements -------------------------------------------------------------------------

double max_overlap(const BodyState& s, const WorldSection& box) {
  if (!s.shapes.empty()) {
    // Shapes: the engine's exact narrow phase with no speculative margin (any overlap has
    // gap < 0 below every threshold); pairs of static/kinematic bodies are not contacts.
    WorldDef d;
    d.world = box;
    d.contact.margin = 0;
    d.time.dt = 1e-300;
    for (std::size_t k = 0; k < s.size(); ++k)
      if (!std::isfinite(s.position[k].x) || !std::isfinite(s.position[k].y))
        throw InvalidArgument("max_overlap: body " + std::to_string(k) + " has a non-finite position");
    ShapeNarrowPhase narrow;
    UniformGridBroadPhase grid;
    std::vector<Contact> contacts;
    narrow.collide(s, d, grid, contacts);
    double worst = 0;
    for (const Contact& c : contacts) worst = std::max(worst, -c.gap);
    return worst;
  }
  const int n = static_cast<int>(s.size());
  double worst = 0;
  for (int k = 0; k < n; ++k) {
    const auto i = static_cast<size_t>(k);
    const Vec2 x = s.position[i];
    const double r = s.radius[i];
    if (box.walls[0]) worst = std::max(worst, r - x.x);
    if (box.walls[1]) worst = std::max(worst, r - (box.width - x.x));
    if (box.walls[2]) worst = std::max(worst, r - x.y);
    if (box.walls[3]) worst = std::max(worst, r - (box.height - x.y));
  }
  UniformGridBroadPhase grid;
  std::vector<std::pair<int, int>> pairs;
  grid.find_pairs(s.position, s.radius, pairs);  // throws for non-finite positions
  for (const auto& [a, b] : pairs) {
    const auto ia = static_cast<size_t>(a), ib = static_cast<size_t>(b);
    worst = std::max(worst, s.radius[ia] + s.radius[ib] - length(s.position[ib] - s.position[ia]));
  }
  return std::max(0.0, worst);
}

bool state_finite(const BodyState& s) {
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (!std::isfinite(s.position[k].x) || !std::isfinite(s.position[k].y) || !std::isfinite(s.angle[k]) ||
        !std::isfinite(s.velocity[k].x) || !std::isfinite(s.velocity[k].y) || !std::isfinite(s.omega[k]))
      return false;
  }
  return true;
}

Vec2 linear_momentum(const BodyState& s) {
  Vec2 p;
  for (std::size_t k = 0; k < s.size(); ++k) p += s.mass[k] * s.velocity[k];
  return p;
}

SolverOptions solver_options(const WorldDef& def) {
  SolverOptions o = dc::solver_options(def.solver);
  o.record_theta = false;
  return o;
}

RunStats run_world(World& world, LcpSolver& solver, const SolverOptions& options,
                   const RunConfig& config) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  RunStats st;
  const WorldDef& def = world.def();
  auto starter = default_warm_starters().make(config.warmstart);
  auto energy = [&] { return world.kinetic_energy() + world.potential_energy(); };

  st.nonfinite = !state_finite(world.bodies());
  st.energy0 = energy();
  double e_min = st.energy0;
  const Vec2 p0 = linear_momentum(world.bodies());
  std::vector<double> top_speed(world.bodies().size(), 0.0);
  auto track_speeds = [&] {
    for (std::size_t k = 0; k < top_speed.size(); ++k)
      top_speed[k] = std::max(top_speed[k], length(world.bodies().velocity[k]));
  };
  track_speeds();
  if (config.collide_repeats > 0 && !st.nonfinite) {
    st.collide_min_ms = 1e300;
    for (int k = 0; k < config.collide_repeats; ++k) {
      const auto c0 = Clock::now();
      world.collide();
      st.collide_min_ms = std::min(st.collide_min_ms, std::chrono::duration<double, std::milli>(Clock::now() - c0).count());
    }
  }
  std::vector<int> sweeps;
  const int rest_from = config.steps - config.rest_window;

  for (int s = 0; s < config.steps && !(st.nonfinite && config.stop_on_nonfinite); ++s) {
    StepReport rep;
    try {
      rep = world.step(solver, options, [&](const World& w) { return starter->initial_guess(StepView{w, nullptr}); });
    } catch (const InvalidArgument& e) {
      // The broad phase refuses non-finite positions and World::step refuses a problem the
      // solver calls invalid: either way the run cannot go on; say which.
      if (!state_finite(world.bodies())) {
        st.nonfinite = true;
      } else {
        ++st.invalid;
        st.garbage = std::string("step ") + std::to_string(s + 1) + ": " + e.what();
      }
      break;
    }
    ++st.steps;
    st.collide_ms += rep.profile.collide_ms;
    const SolveResult& r = rep.solve;
    if (!r.lambda.allFinite()) st.nonfinite = true;
    starter->observe(StepView{world, nullptr}, r.lambda);
    if (rep.rows > 0) {
      ++st.solves;
      st.max_rows = std::max(st.max_rows, rep.rows);
      sweeps.push_back(r.sweeps);
      switch (r.status) {
        case SolveStatus::Converged: ++st.converged; break;
        case SolveStatus::SweepLimit: ++st.sweep_limit; break;
        case SolveStatus::Diverged: ++st.diverged; break;
        case SolveStatus::Failed: ++st.failed; break;
        case SolveStatus::Infeasible: ++st.infeasible; break;
        case SolveStatus::InvalidInput: ++st.invalid; break;
        case SolveStatus::ToleranceReached: ++st.tolerance_reached; break;
      }
      if (std::isnan(r.residual)) {
        st.garbage = "step " + std::to_string(s + 1) + ": NaN residual";
      } else if (r.lambda.allFinite()) {
        // The reported residual must describe the returned λ (no stale or invented figure).
        const double check = natural_residual(world.problem(), r.lambda);
        if (std::isfinite(check) && std::abs(check - r.residual) > 1e-6 * std::max(1.0, check) && st.garbage.empty())
          st.garbage = "step " + std::to_string(s + 1) + ": reported residual " + fmt("%.3g", r.residual) +
                       " but the returned λ has " + fmt("%.3g", check);
        st.max_residual = std::max(st.max_residual, r.residual);
      }
    }
    if (!state_finite(world.bodies())) {
      st.nonfinite = true;
      continue;
    }
    const double pen = max_overlap(world.bodies(), def.world);
    st.max_penetration = std::max(st.max_penetration, pen);
    if (s >= rest_from) st.rest_penetration = std::max(st.rest_penetration, pen);
    const double e = energy();
    st.max_energy_growth = std::max(st.max_energy_growth, e - e_min);
    e_min = std::min(e_min, e);
    st.momentum_drift = std::max(st.momentum_drift, length(linear_momentum(world.bodies()) - p0));
    track_speeds();
  }
  for (std::size_t k = 0; k < top_speed.size(); ++k) {
    st.max_speed = std::max(st.max_speed, top_speed[k]);
    if (std::isfinite(top_speed[k])) st.momentum_scale += world.bodies().mass[k] * top_speed[k];
  }
  if (!sweeps.empty()) {
    std::sort(sweeps.begin(), sweeps.end());
    st.median_sweeps = sweeps[sweeps.size() / 2];
  }
  st.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return st;
}

// ---- the stress table ---------------------------------------------------------------------

namespace {

Scenario make(std::string family, std::string params, WorldDef def, int rest_window, double pen_tol,
              double energy_tol) {
  Scenario s;
  s.family = std::move(family);
  s.params = std::move(params);
  s.run.steps = def.time.steps;
  s.run.rest_window = rest_window;
  s.def = std::move(def);
  s.penetration_tol = pen_tol;
  s.energy_tol = energy_tol;
  return s;
}

/// Σ m |g| · L: the energy to lift every body by L [J].
double lift_energy(const WorldDef& d, const BodyState& s, double L) {
  double m = 0;
  for (double mk : s.mass) m += mk;
  return m * length(d.world.gravity) * L;
}

}  // namespace

std::vector<Scenario> stress_scenarios(bool quick) {
  std::vector<Scenario> out;
  // Tolerances (docs/robustness.md): at rest the penetration may exceed the slop by 1 % of
  // the radius; Baumgarte may lift every body by at most 2 slops' worth of energy.
  auto energy_bound = [](const WorldDef& d, const BodyState* state = nullptr) {
    const BodyState s = state ? *state : make_bodies(d);
    return lift_energy(d, s, 2.0 * d.contact.slop) + 1e-12;
  };

  const std::vector<double> ratios = quick ? std::vector<double>{1e2, 1e6}
                                           : std::vector<double>{1e1, 1e2, 1e3, 1e4, 1e5, 1e6};
  for (bool heavy_top : {true, false})
    for (double q : ratios) {
      WorldDef d = pyramid_mass_ratio(q, heavy_top);
      d.time.steps = quick ? 200 : 500;
      const double eb = energy_bound(d);
      out.push_back(make("mass ratio", std::string(heavy_top ? "pyramid heavy-on-light" : "pyramid light-on-heavy") +
                                           " ratio=" + fmt("%g", q),
                         d, 50, 0.01, eb));
    }
  for (double q : quick ? std::vector<double>{1e6} : std::vector<double>{1e2, 1e3, 1e4, 1e5, 1e6}) {
    WorldDef d = stack_mass_ratio(q);
    d.time.steps = quick ? 200 : 500;
    out.push_back(make("mass ratio", "stack heavy-on-light ratio=" + fmt("%g", q), d, 50, 0.01, energy_bound(d)));
    d.solver.tolerance = 1e-6;  // tolerance mode: PGS must say when it stops short
    out.push_back(make("mass ratio", "stack heavy-on-light ratio=" + fmt("%g", q) + " tol=1e-6", d, 50, 0.01,
                       energy_bound(d)));
  }

  for (double dt : quick ? std::vector<double>{1e-3, 0.05} : std::vector<double>{1e-4, 3e-4, 1e-3, 3e-3, 0.01, 0.02, 0.05}) {
    WorldDef d = small_pile(20, dt);
    d.solver.tolerance = 1e-6;
    d.solver.sweeps = 3000;
    const int rest = static_cast<int>(std::lround(0.2 / dt));
    out.push_back(make("dt", "pile of 20, dt=" + fmt("%g", dt) + " (2 s)", d, rest, 0.01, energy_bound(d)));
  }

  for (int n : quick ? std::vector<int>{50} : std::vector<int>{20, 50, 100}) {
    WorldDef d = column(n);
    d.time.steps = quick ? 300 : 600;
    out.push_back(make("column", "n=" + std::to_string(n) + " sweeps=3000", d, 50, 0.01, energy_bound(d)));
  }

  {
    const std::vector<int> counts = quick ? std::vector<int>{2500, 10000} : std::vector<int>{2500, 10000, 40000};
    const int ref = static_cast<int>(out.size());
    for (int n : counts) {
      WorldDef d = many_bodies(n);
      d.time.steps = quick ? 3 : 10;
      Scenario s = make("many bodies", "n=" + std::to_string(n) + " sweeps=20", d, 0, 1e9, 1e300);
      s.run.warmstart = "zero";
      s.run.collide_repeats = 15;
      if (n != counts.front()) s.linear_ref = ref;
      out.push_back(std::move(s));
    }
  }

  for (double sc : quick ? std::vector<double>{1e-3, 1e2} : std::vector<double>{1e-3, 1e-2, 0.1, 1, 10, 1e2}) {
    WorldDef d = scaled_scene(sc);
    out.push_back(make("radius scale", "s=" + fmt("%g", sc), d, 30, 0.01 * sc, energy_bound(d)));
  }

  for (double mu : {0.0, 0.5, 10.0}) {
    WorldDef d = friction_scene(mu, quick ? 30 : 100);
    d.time.steps = quick ? 300 : 600;
    d.solver.sweeps = quick ? 300 : 3000;
    out.push_back(make("friction", "mu=" + fmt("%g", mu) + " n=" + std::to_string(d.bodies.count) +
                                       " sweeps=" + std::to_string(d.solver.sweeps),
                       d, 50, 0.01, energy_bound(d)));
  }

  {
    WorldDef d = exactly_touching();
    out.push_back(make("degenerate", "exactly touching (row of 4 + 1 on top)", d, 50, 0.01, energy_bound(d)));
  }
  {
    WorldDef d = corners();
    out.push_back(make("degenerate", "corners (4 resting + 1 thrown at 28 m/s)", d, 50, 0.01, energy_bound(d)));
  }
  for (int copies : {2, 5}) {
    // Coincident centres overlap by 2 r: Baumgarte removes it at β(2r − slop)/Δt per step,
    // which is a kick; energy is not expected to be conserved (the verdict says so).
    WorldDef d = coincident_def(true);
    Scenario s = make("degenerate", std::to_string(copies) + " coincident centres (walls, gravity)", d, 50, 0.01, 0);
    s.state = coincident_state(copies);
    s.energy_tol = energy_bound(d, &*s.state);
    out.push_back(std::move(s));
    WorldDef f = coincident_def(false);
    Scenario m = make("momentum", std::to_string(copies) + " coincident centres, no walls/gravity", f, 0, 1e9, 1e300);
    m.state = coincident_state(copies);
    m.check_momentum = true;
    out.push_back(std::move(m));
  }
  for (double q : {1.0, 1e6}) {
    for (double mu : {0.0, 10.0}) {
      WorldDef d = free_collision(quick ? 40 : 100, q, mu);
      Scenario s = make("momentum", "projectile ratio=" + fmt("%g", q) + " mu=" + fmt("%g", mu) + " into " +
                                        std::to_string(d.bodies.count),
                        d, 0, 1e9, 1e300);
      s.check_momentum = true;
      out.push_back(std::move(s));
    }
  }
  // Shapes (docs/design.md §8.1): thin boxes, aspect-10 ellipses, a 20-box stack, a box pyramid. The
  // stack and pyramid use the builtin warm start and 300 sweeps (row-by-row PGS needs that
  // many on two-point manifolds, docs/engine.md).
  {
    WorldDef d = shape_extremes(BodyShape::Box, {2.0, 0.1}, quick ? 20 : 40);
    d.time.steps = quick ? 200 : 400;
    out.push_back(make("shapes", "thin boxes 2 x 0.1, n=" + std::to_string(d.bodies.count), d, 30, 0.02, energy_bound(d)));
  }
  {
    WorldDef d = shape_extremes(BodyShape::Ellipse, {1.0, 0.1}, quick ? 20 : 40);
    d.time.steps = quick ? 200 : 400;
    out.push_back(make("shapes", "ellipses aspect 10 (1 x 0.1), n=" + std::to_string(d.bodies.count), d, 30, 0.02,
                       energy_bound(d)));
  }
  {
    WorldDef d = box_stack(20, {1.0, 1.0});
    d.solver.sweeps = 300;
    d.solver.tolerance = 1e-9;
    d.time.steps = quick ? 300 : 1000;
    out.push_back(make("shapes", "20-box stack, sweeps=300", d, 50, 0.01, energy_bound(d)));
  }
  {
    WorldDef d = box_pyramid(quick ? 10 : 20);
    d.solver.sweeps = 300;
    d.solver.tolerance = 1e-9;
    d.time.steps = quick ? 300 : 600;
    out.push_back(make("shapes", "box pyramid base " + std::to_string(quick ? 10 : 20) + ", sweeps=300", d, 50, 0.01,
                       energy_bound(d)));
  }
  {
    WorldDef d = explicit_scene(30.0, 30.0);
    d.time.steps = 100;
    out.push_back(make("degenerate", "zero bodies", d, 10, 0.0, 0.0));
    d.body.push_back(circle(15.0, 20.0));
    d.time.steps = 300;
    out.push_back(make("degenerate", "one body dropped 19 m", d, 50, 0.01, energy_bound(d)));
  }
  return out;
}

std::string verdict(const Scenario& s, const RunStats& r, const Scenario* ref_s, const RunStats* ref_r) {
  std::vector<std::string> what;
  if (r.nonfinite) what.push_back("NaN/Inf");
  if (!r.garbage.empty()) what.push_back("inconsistent result (" + r.garbage + ")");
  if (r.steps < s.run.steps && !r.nonfinite) what.push_back("stopped after " + std::to_string(r.steps) + " steps");
  if (s.run.rest_window > 0 && r.rest_penetration > s.def.contact.slop + s.penetration_tol)
    what.push_back("rest penetration " + fmt("%.3g", r.rest_penetration) + " m > slop + " +
                   fmt("%.3g", s.penetration_tol));
  if (r.max_energy_growth > s.energy_tol)
    what.push_back("energy growth " + fmt("%.3g", r.max_energy_growth) + " J > " + fmt("%.3g", s.energy_tol));
  if (s.check_momentum && r.momentum_drift > 1e-9 * std::max(r.momentum_scale, 1e-300))
    what.push_back("momentum drift " + fmt("%.3g", r.momentum_drift / std::max(r.momentum_scale, 1e-300)));
  if (ref_s && ref_r && ref_r->collide_min_ms > 0) {
    // Broad + narrow phase must grow at most 2× faster than the body count (see Scenario).
    const double count_ratio = static_cast<double>(s.def.bodies.count) / std::max(1, ref_s->def.bodies.count);
    const double time_ratio = r.collide_min_ms / ref_r->collide_min_ms;
    if (time_ratio > 2.0 * count_ratio)
      what.push_back("collide time x" + fmt("%.2g", time_ratio) + " for x" + fmt("%.2g", count_ratio) + " bodies");
  }
  if (r.diverged + r.failed + r.invalid > 0)
    what.push_back("solver " + std::to_string(r.diverged) + " diverged/" + std::to_string(r.failed) + " failed");
  if (what.empty()) return "held";
  std::string out = "limit reached: ";
  for (std::size_t i = 0; i < what.size(); ++i) out += (i ? "; " : "") + what[i];
  return out;
}

}  // namespace dc::stress
