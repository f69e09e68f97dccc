// box2d3_compare: the same bodies in Box2D v3 (built from source, -DBOX2D3_DIR=…) and in
// DeepContact, the same Δt and number of steps, timed in one process (benchmarks/compare/README.md).
//
//   build/bin/box2d3_compare [--n 100,1000,10000] [--steps 600] [--rounds 3]
//                            [--ours pgs-colored:16,pgs-colored:32,pgs:16,pgs:32]
//                            [--v3 4:30,8:100] [--eq-v3 8:100] [--stack-steps 600] [--pyramid BASE]
//                            [--skip-pile] [--skip-stack]
//
// Scenes: the seed pile scaled to n circles at the seed's density (box side 30·√(n/100) m,
// σ = 4.65·√(n/100) m, r = 1, μ = 0.5, e = 0, Δt = 0.01 s), and the 20-box stack of the stress
// scenes (1 × 1 m boxes on the floor), and with --pyramid BASE the stress scenes' box pyramid. Both engines get the bodies of our World (position,
// angle, velocity, shape, density), the walls, gravity, μ and e; Box2D v3 keeps its own contact
// model (soft step, sub-steps, relaxation, restitution) with sleeping off and one worker.
// A v3 configuration is SUBSTEPS:HERTZ (b2World_Step's sub-step count, b2WorldDef::contactHertz;
// v3's defaults are 4 sub-steps and 30 Hz). Ours is SOLVER:SWEEPS with a fixed sweep count
// (tolerance 0) and the builtin warm start, as `simulate` runs it, and `+KEY=VALUE` suffixes
// change one setting for that configuration (omega, tol, baumgarte, slop, margin, relax, order, symmetric,
// warmscale, warm=none); --trace N prints the pile's motion of ours every N steps.
//
// Reported per configuration:
//  * ms/step: CPU time of the stepping thread (CLOCK_THREAD_CPUTIME_ID) around each step,
//    median over `rounds` runs, the configurations alternated inside each round;
//  * ns per row·pass: v3: the CPU time × the share of solveImpulses + relaxImpulses in
//    b2Profile::step (wall-clock timers whose ratio survives preemption better than their
//    values) ÷ (2 rows per touching point × sub-steps × 2 passes); ours: solver CPU ÷ (rows ×
//    sweeps) including the solver's per-solve set-up, and the marginal sweep cost from a
//    SOLVER:16 and SOLVER:32 pair ((solver ms/step at 32 − at 16) ÷ (rows × 16)), and from it the
//    solver's per-solve set-up (solver ms/step at 16 − 16 sweeps at the marginal cost);
//  * overlap: the largest overlap between touching bodies at the end of the run, by one
//    geometric check for both engines (dc::stress::max_overlap on the final positions);
//  * stack drift: the largest horizontal displacement of a box of the stack from its start;
//  * at the end: the largest body speed, the bodies faster than 0.1 m/s, their mean height;
//  * "ours at equal quality" (piles): of our configurations with overlap and moving bodies at most
//    those of the --eq-v3 configuration, the one with the least median time per step (the
//    question is time at equal quality; fewer sweeps can cost more when the pile settles worse).
#include <box2d/box2d.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "dc/bench/stress_scenarios.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "timed_solver.hpp"

namespace {

using dc::compare::thread_cpu_s;
using dc::compare::TimedSolver;

std::string first_line_of(const std::string& path, const std::string& prefix) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(prefix, 0) == 0) return line;
  return "?";
}

std::string loadavg() { return first_line_of("/proc/loadavg", ""); }

/// The CPU model of /proc/cpuinfo ("model name : …").
std::string cpu_model() {
  const std::string line = first_line_of("/proc/cpuinfo", "model name");
  const size_t colon = line.find(':');
  return colon == std::string::npos ? line : line.substr(colon + 2);
}

/// One engine configuration: Box2D v3 (substeps, contact hertz) or ours (solver, sweeps, and the
/// settings a `+key=value` suffix changes from the scene's: `settings`, applied by run_ours).
struct Config {
  bool v3 = false;
  int substeps = 4;
  float hertz = 30;
  std::string solver;
  int sweeps = 16;
  std::vector<std::pair<std::string, double>> settings;  ///< omega, tol, baumgarte, slop, margin, relax, symmetric, warmscale
  bool warm = true;                                      ///< the builtin warm start (`+warm=none`: none)
  std::string order;  ///< `+order=none|morton|auto`: [bodies] internal_order (empty: the scene's)
  [[nodiscard]] std::string label() const {
    char b[96];
    if (v3) std::snprintf(b, sizeof b, "box2d v3 %d substeps %g Hz", substeps, static_cast<double>(hertz));
    else std::snprintf(b, sizeof b, "ours %s %d sweeps", solver.c_str(), sweeps);
    std::string out = b;
    for (const auto& [key, value] : settings) {
      std::snprintf(b, sizeof b, " %s=%g", key.c_str(), value);
      out += b;
    }
    if (!warm) out += " no warm start";
    if (!order.empty()) out += " order=" + order;
    return out;
  }
  [[nodiscard]] bool same_as(const Config& o) const { return v3 == o.v3 && substeps == o.substeps && hertz == o.hertz; }
};

/// The result of one run of one configuration.
struct Run {
  double cpu_s = 0;          ///< Σ step CPU time
  double solver_cpu_s = 0;   ///< ours: CPU time inside the solver's solve calls
  double pass_share = 0;     ///< v3: (solveImpulses + relaxImpulses) / step, from b2Profile
  double rows_per_step = 0;  ///< LCP rows (ours) or 2 × touching points (v3), mean over steps
  double overlap = 0;        ///< largest overlap at the end [m]
  double drift = 0;          ///< largest |x − x₀| of a body at the end [m]
  double max_speed = 0;      ///< largest |v| of a body at the end [m/s] (is the pile at rest?)
  int moving = 0;            ///< dynamic bodies with |v| > kMoving at the end
  double mean_height = 0;    ///< mean y of the dynamic bodies at the end [m] (a pile that spreads sinks)
  dc::PgsColoredProfile parts;  ///< ours with --profile and solver "pgs-colored": the solver's parts
  dc::StepProfile stages;       ///< ours: Σ of the steps' stage times (wall clock, StepReport::profile) [ms]
};

int g_trace = 0;  ///< --trace N: ours prints the pile's motion every N steps and by height at the end

constexpr double kMoving = 0.1;  ///< [m/s] a body faster than this at the end is "moving"

/// Adds a dynamic body's end speed and height to r's maximum, moving count and height sum.
void add_body(Run& r, double speed, double y) {
  r.max_speed = std::max(r.max_speed, speed);
  if (speed > kMoving) ++r.moving;
  r.mean_height += y;
}

/// Applies one `+key=value` of an --ours item to c (keys: omega, tol, baumgarte, slop, margin, warm).
void parse_setting(const std::string& kv, Config& c) {
  const size_t eq = kv.find('=');
  const std::string key = kv.substr(0, eq), value = eq == std::string::npos ? "" : kv.substr(eq + 1);
  if (key == "warm" && (value == "none" || value == "builtin")) {
    c.warm = value == "builtin";
    return;
  }
  if (key == "order" && !value.empty()) {
    (void)dc::parse_internal_order(value, "--ours order");  // throws for an unknown name
    c.order = value;
    return;
  }
  for (const char* k : {"omega", "tol", "baumgarte", "slop", "margin", "relax", "warmscale", "symmetric"})
    if (key == k && !value.empty()) {
      c.settings.emplace_back(key, std::stod(value));
      return;
    }
  throw CLI::ValidationError("--ours", "unknown setting '" + kv +
                                           "' (omega=, tol=, baumgarte=, slop=, margin=, relax=, order=, warm=none|builtin)");
}

std::vector<Config> parse_configs(const std::string& list, bool v3) {
  std::vector<Config> out;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    const size_t colon = item.find(':');
    if (colon == std::string::npos) throw CLI::ValidationError(v3 ? "--v3" : "--ours", "expected A:B, got '" + item + "'");
    Config c;
    c.v3 = v3;
    if (v3) {
      c.substeps = std::stoi(item.substr(0, colon));
      c.hertz = std::stof(item.substr(colon + 1));
    } else {
      c.solver = item.substr(0, colon);
      std::stringstream parts(item.substr(colon + 1));
      std::string part;
      std::getline(parts, part, '+');
      c.sweeps = std::stoi(part);
      while (std::getline(parts, part, '+')) parse_setting(part, c);
    }
    out.push_back(c);
  }
  return out;
}

/// The seed scene scaled to n circles at the seed's density.
dc::WorldDef scaled_seed(int n) {
  dc::WorldDef def = dc::default_world_def();
  const double s = std::sqrt(n / 100.0);
  def.world.width = def.world.height = 30.0 * s;
  def.bodies.count = n;
  def.bodies.mean = {15.0 * s, 15.0 * s};
  def.bodies.sigma = 4.65 * s;
  return def;
}

// ---- Box2D v3 ---------------------------------------------------------------------------

/// v3 world with our World's bodies (circles and polygons), walls, gravity, μ and e.
b2WorldId make_v3_world(const dc::WorldDef& def, const dc::BodyState& s, const Config& c,
                        std::vector<b2BodyId>& bodies) {
  b2WorldDef wd = b2DefaultWorldDef();
  wd.gravity = {static_cast<float>(def.world.gravity.x), static_cast<float>(def.world.gravity.y)};
  wd.enableSleep = false;
  wd.contactHertz = c.hertz;
  wd.restitutionThreshold = static_cast<float>(def.contact.restitution_threshold);
  const b2WorldId w = b2CreateWorld(&wd);
  b2ShapeDef sd = b2DefaultShapeDef();
  sd.material.friction = static_cast<float>(def.contact.friction);
  sd.material.restitution = static_cast<float>(def.contact.restitution);
  b2BodyDef gd = b2DefaultBodyDef();
  const b2BodyId ground = b2CreateBody(w, &gd);
  const float W = static_cast<float>(def.world.width), H = static_cast<float>(def.world.height);
  const b2Vec2 corners[4][2] = {{{0, 0}, {0, H}}, {{W, 0}, {W, H}}, {{0, 0}, {W, 0}}, {{0, H}, {W, H}}};
  for (int k = 0; k < 4; ++k) {  // left, right, bottom, top (WorldSection::walls order)
    if (!def.world.walls[static_cast<size_t>(k)]) continue;
    const b2Segment seg{corners[k][0], corners[k][1]};
    b2CreateSegmentShape(ground, &sd, &seg);
  }
  bodies.clear();
  for (size_t k = 0; k < s.size(); ++k) {
    b2BodyDef bd = b2DefaultBodyDef();
    bd.type = s.is_dynamic(k) ? b2_dynamicBody : b2_staticBody;
    bd.position = {static_cast<float>(s.position[k].x), static_cast<float>(s.position[k].y)};
    bd.rotation = b2MakeRot(static_cast<float>(s.angle[k]));
    bd.linearVelocity = {static_cast<float>(s.velocity[k].x), static_cast<float>(s.velocity[k].y)};
    bd.angularVelocity = static_cast<float>(s.omega[k]);
    bd.enableSleep = false;
    const b2BodyId b = b2CreateBody(w, &bd);
    sd.density = static_cast<float>(s.density[k]);
    if (s.shapes.empty() || s.shapes.kind[k] == dc::ShapeKind::Circle) {
      const b2Circle circle{{0, 0}, static_cast<float>(s.radius[k])};
      b2CreateCircleShape(b, &sd, &circle);
    } else if (s.shapes.kind[k] == dc::ShapeKind::Polygon && s.shapes.vertex_count(k) <= B2_MAX_POLYGON_VERTICES) {
      b2Vec2 pts[B2_MAX_POLYGON_VERTICES];
      const int nv = s.shapes.vertex_count(k);
      for (int i = 0; i < nv; ++i) {
        const dc::Vec2 v = s.shapes.vertices[static_cast<size_t>(s.shapes.vertex_offset[k] + i)];
        pts[i] = {static_cast<float>(v.x), static_cast<float>(v.y)};
      }
      const b2Hull hull = b2ComputeHull(pts, nv);
      const b2Polygon poly = b2MakePolygon(&hull, 0.0f);
      b2CreatePolygonShape(b, &sd, &poly);
    } else {
      throw std::runtime_error("body " + std::to_string(k) + ": shape has no Box2D v3 counterpart here");
    }
    bodies.push_back(b);
  }
  return w;
}

/// 2 × the touching manifold points of the world (each contact counted once).
double v3_rows(const std::vector<b2BodyId>& bodies, std::vector<b2ContactData>& buf) {
  long points = 0;
  for (const b2BodyId b : bodies) {
    const int cap = b2Body_GetContactCapacity(b);
    if (static_cast<int>(buf.size()) < cap) buf.resize(static_cast<size_t>(cap));
    const int n = b2Body_GetContactData(b, buf.data(), cap);
    for (int i = 0; i < n; ++i) {
      const b2BodyId a = b2Shape_GetBody(buf[static_cast<size_t>(i)].shapeIdA);
      const b2BodyId o = b2Shape_GetBody(buf[static_cast<size_t>(i)].shapeIdB);
      const b2BodyId other = B2_ID_EQUALS(a, b) ? o : a;
      // Count from shape A's body, or from the dynamic side of a contact with a static body.
      if (B2_ID_EQUALS(a, b) || b2Body_GetType(other) != b2_dynamicBody) points += buf[static_cast<size_t>(i)].manifold.pointCount;
    }
  }
  return 2.0 * static_cast<double>(points);
}

Run run_v3(const dc::WorldDef& def, const dc::BodyState& start, const Config& c, int steps) {
  std::vector<b2BodyId> bodies;
  const b2WorldId w = make_v3_world(def, start, c, bodies);
  std::vector<b2ContactData> buf;
  Run r;
  double passes_ms = 0, step_ms = 0, rows = 0;
  int counted = 0;
  const int count_every = std::max(1, steps / 30);  // the row count is sampled outside the timing
  for (int s = 0; s < steps; ++s) {
    const double t0 = thread_cpu_s();
    b2World_Step(w, static_cast<float>(def.time.dt), c.substeps);
    r.cpu_s += thread_cpu_s() - t0;
    const b2Profile p = b2World_GetProfile(w);
    passes_ms += p.solveImpulses + p.relaxImpulses;
    step_ms += p.step;
    if (s % count_every == 0) {
      rows += v3_rows(bodies, buf);
      ++counted;
    }
  }
  r.pass_share = step_ms > 0 ? passes_ms / step_ms : 0;
  r.rows_per_step = rows / std::max(1, counted);
  dc::BodyState end = start;
  int dynamic = 0;
  for (size_t k = 0; k < bodies.size(); ++k) {
    const b2Pos x = b2Body_GetPosition(bodies[k]);
    end.position[k] = {x.x, x.y};
    end.angle[k] = b2Rot_GetAngle(b2Body_GetRotation(bodies[k]));
    r.drift = std::max(r.drift, std::abs(end.position[k].x - start.position[k].x));
    const b2Vec2 v = b2Body_GetLinearVelocity(bodies[k]);
    if (start.is_dynamic(k)) {
      add_body(r, std::hypot(double{v.x}, double{v.y}), x.y);
      ++dynamic;
    }
  }
  r.mean_height /= std::max(1, dynamic);
  r.overlap = dc::stress::max_overlap(end, def.world);
  b2DestroyWorld(w);
  return r;
}

// ---- ours -------------------------------------------------------------------------------

/// --trace: the step's moving bodies, largest speed, kinetic energy, deepest penetration,
/// residual; at the end (bands != 0) the moving bodies by height band of the pile.
void trace_line(const dc::World& world, int step, double residual, int bands = 0) {
  const dc::BodyState& b = world.bodies();
  int moving = 0;
  double vmax = 0, ymax = 0;
  for (size_t k = 0; k < b.size(); ++k) {
    const double v = dc::length(b.velocity[k]);
    moving += v > kMoving;
    vmax = std::max(vmax, v);
    ymax = std::max(ymax, b.position[k].y);
  }
  std::printf("trace step %d: moving %d, max speed %.3f, KE %.1f, max pen %.2f mm, residual %.3g\n", step, moving,
              vmax, world.kinetic_energy(), 1e3 * world.max_penetration(), residual);
  if (bands <= 0) return;
  std::vector<int> count(static_cast<size_t>(bands)), mov(static_cast<size_t>(bands));
  std::vector<double> vsum(static_cast<size_t>(bands)), vy(static_cast<size_t>(bands));
  for (size_t k = 0; k < b.size(); ++k) {
    const auto i = static_cast<size_t>(std::min(bands - 1, static_cast<int>(bands * b.position[k].y / (ymax + 1e-9))));
    ++count[i];
    const double v = dc::length(b.velocity[k]);
    if (v > kMoving) ++mov[i];
    vsum[i] += v;
    vy[i] += b.velocity[k].y;
  }
  for (int i = 0; i < bands; ++i) {
    const auto u = static_cast<size_t>(i);
    std::printf("  band y %.1f–%.1f m: %d bodies, %d moving, mean |v| %.3f, mean v_y %.4f\n", ymax * i / bands,
                ymax * (i + 1) / bands, count[u], mov[u], vsum[u] / std::max(1, count[u]), vy[u] / std::max(1, count[u]));
  }
}

Run run_ours(dc::WorldDef def, const Config& c, int steps, bool profile) {
  def.solver.sweeps = c.sweeps;
  def.solver.tolerance = 0.0;
  for (const auto& [key, value] : c.settings) {
    if (key == "omega") def.solver.omega = value;
    if (key == "tol") def.solver.tolerance = value;
    if (key == "baumgarte") def.contact.baumgarte = value;
    if (key == "slop") def.contact.slop = value;
    if (key == "margin") def.contact.margin = value;
    if (key == "relax") def.solver.relax_sweeps = static_cast<int>(value);
  }
  if (!c.order.empty()) def.bodies.internal_order = dc::parse_internal_order(c.order, "order");
  dc::World world(def);
  const std::vector<dc::Vec2> start = world.bodies().position;
  Run r;
  dc::PgsColoredDef parts_def;
  parts_def.profile = &r.parts;
  TimedSolver solver(profile && c.solver == "pgs-colored" ? dc::make_pgs_colored(parts_def) : dc::make_solver(c.solver));
  dc::SolverOptions o = dc::solver_options(def.solver);
  for (const auto& [key, value] : c.settings)
    if (key == "symmetric") o.symmetric = value != 0;
  o.record_theta = false;
  const auto starter = dc::default_warm_starters().make("builtin");
  const bool builtin = dc::is_builtin_warm_starter(*starter);
  double scale = 1.0;  // +warmscale=: λ⁰ times this (a study of damping; 1 = the starter's guess)
  for (const auto& [key, value] : c.settings)
    if (key == "warmscale") scale = value;
  double rows = 0;
  for (int s = 0; s < steps; ++s) {
    const double t0 = thread_cpu_s();
    // builtin is the engine's own warm start, bit for bit (is_builtin_warm_starter): stepped
    // with it, as a stepping loop would, λ⁰ is formed in the world's kept storage. A scaled
    // warm start (warmscale) goes through the starter's returned guess.
    const dc::StepReport rep =
        c.warm && builtin && scale == 1.0
            ? world.step(solver, o, dc::World::WarmStart::PreviousLambda)
            : world.step(solver, o, [&](const dc::World& w) {
                if (!c.warm) return Eigen::VectorXd();
                Eigen::VectorXd g = starter->initial_guess(dc::StepView{w, nullptr});
                if (scale != 1.0) g *= scale;
                return g;
              });
    if (c.warm) starter->observe(dc::StepView{world, nullptr}, rep.solve.lambda);
    r.cpu_s += thread_cpu_s() - t0;
    rows += rep.rows;
    r.stages.collide_ms += rep.profile.collide_ms;
    r.stages.broad_phase_ms += rep.profile.broad_phase_ms;
    r.stages.assemble_ms += rep.profile.assemble_ms;
    r.stages.warmstart_ms += rep.profile.warmstart_ms;
    r.stages.solve_ms += rep.profile.solve_ms;
    r.stages.integrate_ms += rep.profile.integrate_ms;
    if (g_trace > 0 && (s + 1) % g_trace == 0) trace_line(world, s + 1, rep.solve.residual);
  }
  if (g_trace > 0) trace_line(world, steps, 0.0, 10);
  r.solver_cpu_s = solver.cpu_s;
  r.rows_per_step = rows / std::max(1, steps);
  int dynamic = 0;
  for (size_t k = 0; k < start.size(); ++k) {
    r.drift = std::max(r.drift, std::abs(world.bodies().position[k].x - start[k].x));
    if (world.bodies().is_dynamic(k)) {
      add_body(r, dc::length(world.bodies().velocity[k]), world.bodies().position[k].y);
      ++dynamic;
    }
  }
  r.mean_height /= std::max(1, dynamic);
  r.overlap = dc::stress::max_overlap(world.bodies(), def.world);
  return r;
}

// ---- the table ----------------------------------------------------------------------------

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

/// The row "ours at equal quality": of our configurations whose overlap is at most the overlap of
/// the quality reference `ref` (a v3 configuration) and whose moving bodies are no more than its,
/// the one with the lowest median ms/step (ties: fewer sweeps); −1 when there is no reference
/// or none qualifies.
int equal_quality(const std::vector<Config>& configs, const std::vector<Run>& last, const std::vector<double>& med,
                  int ref) {
  if (ref < 0) return -1;
  int best = -1;
  for (size_t i = 0; i < configs.size(); ++i) {
    const Run& bar = last[static_cast<size_t>(ref)];
    if (configs[i].v3 || last[i].overlap > bar.overlap || last[i].moving > bar.moving) continue;
    const auto b = static_cast<size_t>(best);
    if (best < 0 || med[i] < med[b] || (med[i] == med[b] && configs[i].sweeps < configs[b].sweeps))
      best = static_cast<int>(i);
  }
  return best;
}

/// One table row: ms/step, rows, per-pass costs, overlap, speed, the last column and the ratio to
/// the quality reference `ref_ms` (0: none).
void print_row(const std::string& label, const Config& c, const Run& r, const std::vector<double>& ms, double med,
               double marginal, double setup, int steps, bool stack, double first_ms, double ref_ms) {
  const double per_pass = c.v3 ? 1e6 * med * r.pass_share / std::max(1.0, r.rows_per_step * c.substeps * 2)
                               : 1e9 * r.solver_cpu_s / steps / std::max(1.0, r.rows_per_step * c.sweeps);
  char last_col[32], marginal_col[32] = "–", setup_col[32] = "–", ref_col[32] = "–", solver_col[32] = "–";
  if (!c.v3) std::snprintf(solver_col, sizeof solver_col, "%.4f", 1e3 * r.solver_cpu_s / steps);
  if (!std::isnan(marginal)) std::snprintf(marginal_col, sizeof marginal_col, "%.2f", marginal);
  if (!std::isnan(setup)) std::snprintf(setup_col, sizeof setup_col, "%.3f", setup);
  if (ref_ms > 0) std::snprintf(ref_col, sizeof ref_col, "%.2f", med / ref_ms);
  if (stack) std::snprintf(last_col, sizeof last_col, "%.2f", 1e3 * r.drift);
  else std::snprintf(last_col, sizeof last_col, "%.2f", first_ms > 0 ? med / first_ms : 0.0);
  std::printf("| %s | %.4f | %.4f–%.4f | %s | %.0f | %.2f | %s | %s | %.2f | %.3f | %d | %.3f | %s | %s |\n",
              label.c_str(), med, *std::min_element(ms.begin(), ms.end()), *std::max_element(ms.begin(), ms.end()),
              solver_col, r.rows_per_step, per_pass, marginal_col, setup_col, 1e3 * r.overlap, r.max_speed, r.moving,
              r.mean_height, ref_col, last_col);
}

/// Runs every configuration `rounds` times, alternated, on `def`; prints one row each, then the
/// row "ours at equal quality" against the quality reference `eq_ref` (a v3 configuration in
/// `configs`, or none). profile: then the parts of pgs-colored's solves (PgsColoredProfile).
void compare(const std::string& title, const dc::WorldDef& def, const std::vector<Config>& configs, int steps,
             int rounds, bool stack, const Config* eq_ref, bool profile) {
  const dc::World initial(def);
  std::vector<std::vector<double>> ms(configs.size());
  std::vector<Run> last(configs.size());
  for (int round = 0; round < rounds; ++round)
    for (size_t i = 0; i < configs.size(); ++i) {
      last[i] = configs[i].v3 ? run_v3(def, initial.bodies(), configs[i], steps) : run_ours(def, configs[i], steps, profile);
      ms[i].push_back(1e3 * last[i].cpu_s / steps);
    }
  std::vector<double> med(configs.size());
  int ref = -1;
  for (size_t i = 0; i < configs.size(); ++i) {
    med[i] = median(ms[i]);
    if (ref < 0 && eq_ref != nullptr && configs[i].same_as(*eq_ref)) ref = static_cast<int>(i);
  }
  const double ref_ms = ref >= 0 ? med[static_cast<size_t>(ref)] : 0.0;
  std::printf("\n## %s: %zu bodies, %d steps of %g s, %d rounds (load %s)\n", title.c_str(), initial.bodies().size(),
              steps, def.time.dt, rounds, loadavg().c_str());
  std::printf("| configuration | ms/step (median) | min–max | solver ms/step | rows/step | ns/row·pass | marginal ns/row·sweep | "
              "solver set-up ms/step | overlap mm | max speed m/s | moving | mean height m | ms/step ÷ %s | %s |\n"
              "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
              ref >= 0 ? configs[static_cast<size_t>(ref)].label().c_str() : "quality reference",
              stack ? "drift mm" : "ms/step ÷ first");
  const double first_ms = configs.empty() ? 0 : med[0];
  for (size_t i = 0; i < configs.size(); ++i) {
    const Config& c = configs[i];
    double marginal = NAN, setup = NAN;
    for (size_t j = 0; j < configs.size() && !c.v3; ++j)  // the same solver and settings at twice the sweeps
      if (!configs[j].v3 && configs[j].solver == c.solver && configs[j].settings == c.settings &&
          configs[j].warm == c.warm && configs[j].order == c.order && configs[j].sweeps == 2 * c.sweeps) {
        const double a = last[i].solver_cpu_s / steps, b = last[j].solver_cpu_s / steps;
        const double rows = 0.5 * (last[i].rows_per_step + last[j].rows_per_step);
        marginal = 1e9 * (b - a) / std::max(1.0, rows * c.sweeps);
        setup = 1e3 * (a - (b - a));
      }
    print_row(c.label(), c, last[i], ms[i], med[i], marginal, setup, steps, stack, first_ms, ref_ms);
  }
  const int eq = equal_quality(configs, last, med, ref);
  if (eq >= 0) {
    const auto e = static_cast<size_t>(eq);
    print_row("ours at equal quality: " + configs[e].label(), configs[e], last[e], ms[e], med[e], NAN, NAN, steps,
              stack, first_ms, ref_ms);
  }
  for (size_t i = 0; i < configs.size() && profile; ++i) {
    const dc::PgsColoredProfile& q = last[i].parts;
    if (configs[i].v3) continue;
    const dc::StepProfile& g = last[i].stages;
    const double w = 1.0 / steps;  // Σ ms → ms per step
    std::printf("\nstep stages, %s (wall ms/step, last round): collide %.4f (broad phase %.4f), assemble %.4f, "
                "warm start %.4f, solve %.4f, integrate %.4f\n",
                configs[i].label().c_str(), w * g.collide_ms, w * g.broad_phase_ms, w * g.assemble_ms,
                w * g.warmstart_ms, w * g.solve_ms, w * g.integrate_ms);
    if (q.solves == 0) continue;
    const double k = 1e3 / steps;  // CPU ms per step
    std::printf("\nsolver parts, %s (CPU ms/step, last round): checks %.4f, colouring %.4f, ordering %.4f, "
                "pack %.4f, du0 %.4f, sweeps %.4f, unpermute %.4f, residual %.4f\n",
                configs[i].label().c_str(), k * q.checks, k * q.coloring, k * q.ordering, k * q.pack, k * q.du0,
                k * q.sweeps, k * q.unpermute, k * q.residual);
  }
  if (ref >= 0) {
    const Config& r = configs[static_cast<size_t>(ref)];
    char pick[160] = "none qualifies";
    if (eq >= 0)
      std::snprintf(pick, sizeof pick, "%s at %.2f× its time", configs[static_cast<size_t>(eq)].label().c_str(),
                    med[static_cast<size_t>(eq)] / ref_ms);
    std::printf("\nOurs at equal quality: of our configurations whose overlap is at most %s's (%.2f mm) with at "
                "most its moving bodies (%d), the one with the least time per step: %s.\n",
                r.label().c_str(), 1e3 * last[static_cast<size_t>(ref)].overlap, last[static_cast<size_t>(ref)].moving,
                pick);
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::string ns = "100,1000,10000", ours = "pgs-colored:16,pgs-colored:32,pgs:16,pgs:32", v3 = "4:30,8:100";
  std::string eq_v3 = "8:100";
  int steps = 600, rounds = 3, stack_steps = 600, pyramid = 0;
  bool skip_pile = false, skip_stack = false, profile = false;
  CLI::App app{"Box2D v3 vs DeepContact: the scaled seed pile and a 20-box stack, ms per step and quality"};
  app.add_option("--n", ns, "Body counts of the scaled seed pile, comma-separated (default 100,1000,10000)");
  app.add_option("--steps", steps, "Steps of each pile run (default 600)")->check(CLI::PositiveNumber);
  app.add_option("--rounds", rounds, "Alternated rounds; ms/step is their median (default 3)")->check(CLI::PositiveNumber);
  app.add_option("--ours", ours, "Our configurations SOLVER:SWEEPS, comma-separated");
  app.add_option("--v3", v3, "Box2D v3 configurations SUBSTEPS:CONTACT_HERTZ, comma-separated (v3 defaults: 4:30)");
  app.add_option("--stack-steps", stack_steps, "Steps of the 20-box stack run (default 600)")->check(CLI::PositiveNumber);
  app.add_option("--pyramid", pyramid, "Also run the box pyramid of this base (0 = not; --stack-steps steps)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--eq-v3", eq_v3,
                 "The v3 configuration SUBSTEPS:CONTACT_HERTZ of --v3 whose overlap sets the bar of the row "
                 "'ours at equal quality' on the piles (default 8:100; empty: no such row)");
  app.add_flag("--profile", profile,
               "Print the parts of pgs-colored's solves (checks, colouring, …, sweeps, residual) per configuration");
  app.add_option("--trace", g_trace, "Ours: print the pile's motion every N steps and by height at the end (0: not)");
  app.add_flag("--skip-pile", skip_pile, "Do not run the piles");
  app.add_flag("--skip-stack", skip_stack, "Do not run the box stack");
  CLI11_PARSE(app, argc, argv);
  try {
    std::vector<Config> configs = parse_configs(v3, true);
    for (const Config& c : parse_configs(ours, false)) configs.push_back(c);
    const std::vector<Config> eq = parse_configs(eq_v3, true);
    const Config* eq_ref = eq.empty() ? nullptr : &eq.front();
    std::printf("CPU: %s\nBox2D v3 %d.%d.%d, one worker, sleeping off; load at start %s\n",
                cpu_model().c_str(), b2GetVersion().major, b2GetVersion().minor,
                b2GetVersion().revision, loadavg().c_str());
    if (!skip_stack) {
      dc::WorldDef d = dc::stress::box_stack(20, {1.0, 1.0});
      compare("20-box stack", d, configs, stack_steps, rounds, true, nullptr, profile);
    }
    if (pyramid > 0)
      compare("box pyramid, base " + std::to_string(pyramid), dc::stress::box_pyramid(pyramid), configs, stack_steps,
              rounds, true, nullptr, profile);
    if (!skip_pile) {
      std::stringstream ss(ns);
      std::string item;
      while (std::getline(ss, item, ','))
        if (!item.empty()) compare("seed pile", scaled_seed(std::stoi(item)), configs, steps, rounds, false, eq_ref, profile);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "box2d3_compare: %s\n", e.what());
    return 1;
  }
  return 0;
}
