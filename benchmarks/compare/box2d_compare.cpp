// box2d_compare: the same scene in Box2D 2.4.1 (Debian's libbox2d-dev) and in DeepContact,
// the same steps and the same number of velocity iterations (our sweeps), timed in one
// process. Built only when CMake finds Box2D (bench/CMakeLists.txt).
//
//   build/bin/box2d_compare [--scene scenes/seed.toml] [--steps N] [--iterations K]
//                             [--solver pgs|pgs-colored|…] [--scenario circles|box-stack|box-pyramid]
//                             [--row-by-row]   (pgs: SolverOptions::block_manifolds = false)
//
// Reported (CPU time of this thread, getrusage-free clock_gettime(CLOCK_THREAD_CPUTIME_ID)):
//  * Box2D: the whole run's CPU time; ns per contact point per velocity iteration: the run's
//    CPU time × the velocity iterations' share of the step (b2Profile::solveVelocity /
//    b2Profile::step, Box2D's own wall-clock timers, whose ratio survives preemption better
//    than their values), and the whole step's CPU time per point-iteration (upper bound). A
//    point is two rows (normal + tangent), so the per-row figure is half the per-point one.
//  * ours: the whole run's CPU time, and the solver's CPU time per row per sweep (a timing
//    wrapper around the solver's solve call), with the builtin warm start as `simulate` uses.
//
// The scene is read with our loader, so both engines get the same bodies (positions, radii,
// densities, velocities), gravity, box, Δt, μ and e. Box2D keeps its own contact model
// (soft position correction, b2_linearSlop = 0.005 = our slop, restitution threshold 1 m/s
// = ours); sleeping is off in Box2D (our engine has none), position iterations default to 3.
// Scenarios box-stack (20 boxes of 1 × 1 m) and box-pyramid (base 20) put the same boxes in both
// engines (ours as [[body]] shape = "box", density 1) and also report stability after the run:
// drift = the largest horizontal displacement of a box from its start [m] (and as a share of the
// box width), penetration = the deepest overlap among touching contact points at the end [m].
#include <box2d/box2d.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "timed_solver.hpp"

namespace {

using dc::compare::thread_cpu_s;
using dc::compare::TimedSolver;

struct Args {
  std::string scene = std::string(DC_SOURCE_DIR) + "/scenes/seed.toml";
  int steps = -1;       // −1: the scene's
  int iterations = -1;  // −1: the scene's solver.sweeps
  int position_iterations = 3;
  std::string solver;   // "": the scene's
  std::string scenario = "circles";
  bool skip_ours = false;
  bool skip_box2d = false;
  bool row_by_row = false;  // pgs without the two-point manifold block
};

/// Static box walls [0, W] × [0, H] as two-sided edges (only the walls the scene enables).
void add_walls(b2World& w, const dc::WorldDef& def) {
  b2BodyDef bd;
  b2Body* ground = w.CreateBody(&bd);
  const float W = static_cast<float>(def.world.width), H = static_cast<float>(def.world.height);
  const b2Vec2 corners[4][2] = {{{0, 0}, {0, H}}, {{W, 0}, {W, H}}, {{0, 0}, {W, 0}}, {{0, H}, {W, H}}};
  for (int k = 0; k < 4; ++k) {  // left, right, bottom, top (WorldSection::walls order)
    if (!def.world.walls[static_cast<size_t>(k)]) continue;
    b2EdgeShape e;
    e.SetTwoSided(corners[k][0], corners[k][1]);
    b2FixtureDef fd;
    fd.shape = &e;
    fd.friction = static_cast<float>(def.contact.friction);
    fd.restitution = static_cast<float>(def.contact.restitution);
    ground->CreateFixture(&fd);
  }
}

b2Body* add_dynamic(b2World& w, const b2Shape& shape, b2Vec2 x, float angle, b2Vec2 v, float omega, float density,
                    const dc::WorldDef& def) {
  b2BodyDef bd;
  bd.type = b2_dynamicBody;
  bd.position = x;
  bd.angle = angle;
  bd.linearVelocity = v;
  bd.angularVelocity = omega;
  b2Body* b = w.CreateBody(&bd);
  b2FixtureDef fd;
  fd.shape = &shape;
  fd.density = density;
  fd.friction = static_cast<float>(def.contact.friction);
  fd.restitution = static_cast<float>(def.contact.restitution);
  b->CreateFixture(&fd);
  return b;
}

/// Centres of the 1 × 1 m boxes of a box scenario, resting on the floor, centred in the box.
std::vector<dc::Vec2> box_positions(const dc::WorldDef& def, const std::string& scenario) {
  std::vector<dc::Vec2> out;
  const double cx = def.world.width / 2;
  if (scenario == "box-stack") {
    for (int k = 0; k < 20; ++k) out.push_back({cx, 0.5 + 1.0 * k});
  } else if (scenario == "box-pyramid") {
    const int base = 20;
    for (int row = 0; row < base; ++row)
      for (int k = 0; k < base - row; ++k) out.push_back({cx + (k - 0.5 * (base - row - 1)) * 1.0, 0.5 + 1.0 * row});
  } else {
    throw CLI::ValidationError("--scenario", "expected circles, box-stack or box-pyramid, got '" + scenario + "'");
  }
  return out;
}

/// The scene's bodies (circles), or a box stack / pyramid (1 × 1 boxes) on the floor.
void populate(b2World& w, const dc::WorldDef& def, const std::string& scenario) {
  add_walls(w, def);
  if (scenario == "circles") {
    const dc::World ours(def);  // generates the seeded circles exactly as a simulation does
    const dc::BodyState& s = ours.bodies();
    for (size_t k = 0; k < s.size(); ++k) {
      b2CircleShape c;
      c.m_radius = static_cast<float>(s.radius[k]);
      const float density = static_cast<float>(s.mass[k] / (M_PI * s.radius[k] * s.radius[k]));
      add_dynamic(w, c, {static_cast<float>(s.position[k].x), static_cast<float>(s.position[k].y)},
                  static_cast<float>(s.angle[k]), {static_cast<float>(s.velocity[k].x), static_cast<float>(s.velocity[k].y)},
                  static_cast<float>(s.omega[k]), density, def);
    }
    return;
  }
  b2PolygonShape box;
  box.SetAsBox(0.5f, 0.5f);
  for (const dc::Vec2 x : box_positions(def, scenario))
    add_dynamic(w, box, {static_cast<float>(x.x), static_cast<float>(x.y)}, 0, {0, 0}, 0, 1.0f, def);
}

/// Our definition of a box scenario: the scene's world, solver and contact settings, no
/// generated bodies, the boxes as explicit [[body]] entries (1 × 1 m, density 1 kg/m²).
dc::WorldDef box_scenario_def(dc::WorldDef def, const std::string& scenario) {
  def.bodies.count = 0;
  def.body.clear();
  for (const dc::Vec2 x : box_positions(def, scenario)) {
    dc::BodyDef b;
    b.shape = dc::BodyShape::Box;
    b.size = {1.0, 1.0};
    b.position = x;
    b.density = 1.0;
    def.body.push_back(b);
  }
  return def;
}

struct Box2dRun {
  double cpu_s = 0, solve_velocity_ms = 0, step_ms = 0;
  long points = 0;  // Σ over steps of touching contact points
  double drift = 0, penetration = 0;  // at the end [m] (box scenarios)
};

Box2dRun run_box2d(const dc::WorldDef& def, const Args& a, int steps, int iterations) {
  b2World w(b2Vec2(static_cast<float>(def.world.gravity.x), static_cast<float>(def.world.gravity.y)));
  w.SetAllowSleeping(false);
  populate(w, def, a.scenario);
  Box2dRun r;
  const double t0 = thread_cpu_s();
  for (int s = 0; s < steps; ++s) {
    w.Step(static_cast<float>(def.time.dt), iterations, a.position_iterations);
    const b2Profile& p = w.GetProfile();
    r.solve_velocity_ms += p.solveVelocity;
    r.step_ms += p.step;
    for (b2Contact* c = w.GetContactList(); c; c = c->GetNext())
      if (c->IsTouching() && c->IsEnabled()) r.points += c->GetManifold()->pointCount;
  }
  r.cpu_s = thread_cpu_s() - t0;
  if (a.scenario != "circles") {
    const std::vector<dc::Vec2> start = box_positions(def, a.scenario);
    size_t k = start.size();  // Box2D's body list is newest first
    for (b2Body* b = w.GetBodyList(); b; b = b->GetNext()) {
      if (b->GetType() != b2_dynamicBody || k == 0) continue;
      --k;
      r.drift = std::max(r.drift, std::abs(static_cast<double>(b->GetPosition().x) - start[k].x));
    }
    for (b2Contact* c = w.GetContactList(); c; c = c->GetNext()) {
      if (!c->IsTouching()) continue;
      b2WorldManifold wm;
      c->GetWorldManifold(&wm);
      for (int q = 0; q < c->GetManifold()->pointCount; ++q)
        r.penetration = std::max(r.penetration, -static_cast<double>(wm.separations[q]));
    }
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  CLI::App app{"Box2D 2.4.1 vs DeepContact on the same scene, same steps and velocity iterations"};
  app.add_option("--scene", a.scene, "Scene file (TOML; default scenes/seed.toml)");
  app.add_option("--steps", a.steps, "Steps (default: the scene's time.steps)");
  app.add_option("--iterations", a.iterations, "Velocity iterations = our sweeps (default: the scene's solver.sweeps)");
  app.add_option("--position-iterations", a.position_iterations, "Box2D position iterations (default 3)");
  app.add_option("--solver", a.solver, "Our solver (default: the scene's solver.name)");
  app.add_option("--scenario", a.scenario, "circles (the scene's bodies), box-stack (20 boxes) or box-pyramid (base 20)");
  app.add_flag("--skip-ours", a.skip_ours, "Run Box2D only");
  app.add_flag("--skip-box2d", a.skip_box2d, "Run our engine only");
  app.add_flag("--row-by-row", a.row_by_row,
               "pgs: solve a two-point manifold's normal rows one by one instead of as one 2x2 block");
  CLI11_PARSE(app, argc, argv);
  try {
    dc::WorldDef def = dc::load_scene(a.scene);
    if (a.solver.empty()) a.solver = dc::to_string(def.solver.name);
    const int steps = a.steps >= 0 ? a.steps : def.time.steps;
    const int iterations = a.iterations >= 0 ? a.iterations : def.solver.sweeps;
    def.solver.sweeps = iterations;
    def.solver.tolerance = 0.0;  // fixed iterations, like Box2D
    std::printf("scene %s, scenario %s, %d steps, %d velocity iterations (our sweeps), box2d position iterations %d\n",
                a.scene.c_str(), a.scenario.c_str(), steps, iterations, a.position_iterations);
    double box2d_cpu = 0, ours_cpu = 0;
    if (!a.skip_box2d) {
      const Box2dRun b = run_box2d(def, a, steps, iterations);
      box2d_cpu = b.cpu_s;
      const double pi = static_cast<double>(b.points) * iterations;
      // b2Profile's timers are wall clock (inflated by preemption on a loaded machine); their
      // ratio gives the velocity iterations' share of the step, applied to the CPU time.
      const double share = b.step_ms > 0 ? b.solve_velocity_ms / b.step_ms : 1.0;
      const double ns_point = 1e9 * b.cpu_s * share / std::max(1.0, pi);
      std::printf("box2d 2.4.1: run CPU %.3f s; contact points/step %.1f; velocity iterations %.0f %% of the step; "
                  "ns per point per velocity iteration %.2f (CPU; whole step: %.2f), per row (2 per point) %.2f\n",
                  b.cpu_s, static_cast<double>(b.points) / std::max(1, steps), 100 * share, ns_point,
                  1e9 * b.cpu_s / std::max(1.0, pi), 0.5 * ns_point);
      if (a.scenario != "circles")
        std::printf("box2d 2.4.1 stability: drift %.3e m (%.3f %% of the box width), penetration %.3e m\n", b.drift,
                    100 * b.drift, b.penetration);
    }
    if (!a.skip_ours) {
      {
        const bool boxes = a.scenario != "circles";
        dc::World world(boxes ? box_scenario_def(def, a.scenario) : def);
        const std::vector<dc::Vec2> start = world.bodies().position;
        TimedSolver solver(dc::make_solver(a.solver));
        dc::SolverOptions o = dc::solver_options(def.solver);
        o.record_theta = false;
        o.block_manifolds = !a.row_by_row;
        const dc::WarmStarterRegistry reg = dc::default_warm_starters();
        auto starter = reg.make("builtin");
        long rows = 0, points = 0;
        const double t0 = thread_cpu_s();
        for (int s = 0; s < steps; ++s) {
          const dc::StepReport r = world.step(solver, o, [&](const dc::World& w) {
            return starter->initial_guess(dc::StepView{w, nullptr});
          });
          starter->observe(dc::StepView{world, nullptr}, r.solve.lambda);
          rows += r.rows;
          points += static_cast<long>(world.contacts().size());
        }
        ours_cpu = thread_cpu_s() - t0;
        if (boxes) {
          world.collide();  // the contacts of the final state
          double drift = 0, penetration = 0;
          for (size_t k = 0; k < start.size(); ++k)
            drift = std::max(drift, std::abs(world.bodies().position[k].x - start[k].x));
          for (const dc::Contact& c : world.contacts()) penetration = std::max(penetration, -c.gap);
          std::printf("ours stability: drift %.3e m (%.3f %% of the box width), penetration %.3e m; "
                      "contact points/step %.1f, solver ns per point per sweep %.2f\n",
                      drift, 100 * drift, penetration, static_cast<double>(points) / std::max(1, steps),
                      1e9 * solver.cpu_s / std::max(1.0, static_cast<double>(points) * iterations));
        }
        std::printf("ours (%s%s, builtin warm start): run CPU %.3f s; rows/step %.1f; solver CPU %.3f s, "
                    "ns per row per sweep %.2f\n",
                    a.solver.c_str(), a.row_by_row ? ", row by row" : "", ours_cpu, static_cast<double>(rows) / std::max(1, steps), solver.cpu_s,
                    1e9 * solver.cpu_s / std::max(1.0, solver.row_sweeps));
      }
    }
    if (box2d_cpu > 0 && ours_cpu > 0) std::printf("run CPU ratio ours / box2d: %.3f\n", ours_cpu / box2d_cpu);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "box2d_compare: %s\n", e.what());
    return 1;
  }
  return 0;
}
