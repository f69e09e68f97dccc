#pragma once
// The configuration of a world, Box2D-style: plain structs whose member initialisers ARE
// the documented defaults. The defaults reproduce the seed scene of the thesis
// (docs/design.md §3): 100 circles of radius 1 in a 30 × 30 box, Δt = 0.01 s, 600 steps,
// 3000 PGS sweeps. Every field maps 1:1 to a TOML key `[section] key` (docs/scenes.md).
// Enumerations are typed (SolverId, BodyShape, Motion, BodyOrder, InternalOrder); their
// names are read and written only where users give them: scene files and `--set`
// (scene.hpp), CLI options and Python arguments.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dc/core/vec2.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/shape.hpp"

namespace dc {

/// Numbering of the generated bodies (`[bodies] order`, BodiesSection::order).
enum class BodyOrder : std::uint8_t {
  Creation,  ///< "creation": the order they were placed in
  Morton,    ///< "morton": renumbered by the Morton code of their initial cell
};
/// Order in which the engine stores and steps the bodies (`[bodies] internal_order`).
enum class InternalOrder : std::uint8_t {
  None,    ///< "none": storage order = external order
  Morton,  ///< "morton": Morton order of the current cell, re-sorted as it decays
  Auto,    ///< "auto": Morton where it pays (internal_order_auto_min_bodies), else none
};
/// "auto" keeps the Morton working copy for worlds that start with at least this many bodies,
/// all dynamic circles: below it the bodies, contacts and rows of a step fit in the caches
/// anyway and the translation to the public views costs more than the locality saves
/// (docs/engine.md "Step cost against size"). Smaller worlds, and any with shapes, static or
/// kinematic bodies, step in storage order = external order, as with "none".
inline constexpr int internal_order_auto_min_bodies = 20000;
/// "creation" / "morton"; "none" / "morton" / "auto" (the scene files' spelling).
const char* to_string(BodyOrder o);
const char* to_string(InternalOrder o);
/// Parse the scene spelling; throw ConfigError "<key>: expected \"creation\" or \"morton\", got
/// \"<name>\"" (resp. "none", "morton" or "auto") otherwise.
BodyOrder parse_body_order(const std::string& name, const std::string& key);
InternalOrder parse_internal_order(const std::string& name, const std::string& key);

struct WorldSection {
  double width = 30.0;            ///< box extent along x [m]; the box is [0, width] × [0, height]
  double height = 30.0;           ///< box extent along y [m]
  Vec2 gravity{0.0, -9.81};       ///< gravitational acceleration [m/s²]
  /// Which walls exist: left (x = 0), right (x = width), bottom (y = 0), top (y = height).
  std::array<bool, 4> walls{true, true, true, true};

  friend bool operator==(const WorldSection&, const WorldSection&) = default;
};

struct TimeSection {
  double dt = 0.01;   ///< time step Δt [s]
  int steps = 600;    ///< number of steps a simulation runs

  friend bool operator==(const TimeSection&, const TimeSection&) = default;
};

struct ContactSection {
  double friction = 0.5;     ///< Coulomb coefficient μ (0 ⇒ no tangent rows at all)
  /// e: a contact that hits with relative normal velocity v_a (stored when its row first acts,
  /// docs/design.md §8.3, restitution.hpp) leaves with −e·v_a, if |v_a| > restitution_threshold.
  double restitution = 0.0;
  double baumgarte = 0.2;    ///< β: fraction of penetration beyond slop removed per step
  double slop = 0.005;       ///< allowed penetration [m] before Baumgarte acts
  /// Speculative margin [m]: pairs closer than margin + (|v_a|+|v_b|)·Δt get a contact
  /// row, so fast bodies cannot tunnel; the row only acts once the gap would close.
  double margin = 0.02;
  /// Approach speed [m/s] at or below which an impact is perfectly inelastic (no bounce).
  /// Compared with |v_a|, the relative normal speed the contact had when its row first acted
  /// (not the current, already-stopped velocity). It keeps resting and slowly settling contacts
  /// quiet: a body resting under gravity re-approaches at only ~|g|·Δt per step (0.1 m/s at the
  /// defaults), so any threshold above that stops the jitter a tiny bounce would cause.
  double restitution_threshold = 1.0;

  friend bool operator==(const ContactSection&, const ContactSection&) = default;
};

struct SolverSection {
  /// LCP solver (make_solver; spelled pgs, pgs-colored[:N[:K]], pgs-assembled, psor, jacobi,
  /// lemke, newton, newton-sparse, nncg). The default pgs-colored sweeps in "pgs"'s row order
  /// (its colours follow contact order), one thread, SIMD kernels.
  SolverId name{SolverKind::PgsColored};
  int sweeps = 3000;         ///< maximum sweeps per step (the seed's fixed 3000)
  double tolerance = 0.0;    ///< stop when θ_k ≤ tolerance [N]; 0 ⇒ always run `sweeps` sweeps
  double omega = 1.0;        ///< relaxation for psor (1 = PGS)
  /// Sweeps of the bias-free relax pass after each solve (0 = none, the default): World::step
  /// moves the bodies with the solve's velocities (Baumgarte's position bias included) and
  /// keeps, as their new velocities, those of `relax_sweeps` more sweeps without that bias,
  /// from the solve's λ (docs/engine.md "Relax pass"). Time per step: one more solve of
  /// relax_sweeps sweeps.
  int relax_sweeps = 0;

  friend bool operator==(const SolverSection&, const SolverSection&) = default;
};

struct BodiesSection {
  int count = 100;               ///< generated circles (0 = none)
  double radius = 1.0;           ///< radius of generated circles [m]
  double density = 1.0;          ///< areal density [kg/m²]
  Vec2 mean{15.0, 15.0};         ///< mean of the 2D Gaussian of initial centres [m]
  double sigma = 4.65;           ///< standard deviation per axis [m] (seed: 1.2·√15)
  std::uint64_t seed = 1;        ///< seed of the GSL mt19937 stream that places them
  int max_attempts = 1000000;    ///< rejection-sampling budget before giving up (error)
  // Shape of the generated bodies (as [[body]]; shape.hpp). Non-circles are placed by their
  // bounding circle and get a uniformly random angle (drawn after the position).
  BodyShape shape = BodyShape::Circle;  ///< "circle" | "box" | "polygon" | "ellipse"
  Vec2 size{1.0, 1.0};           ///< box: width, height [m]
  int sides = 0;                 ///< regular polygon: sides (3..16), circumradius = radius
  std::vector<Vec2> vertices;    ///< explicit convex polygon, body frame, CCW [m]
  Vec2 semi_axes{1.0, 0.5};      ///< ellipse: a, b [m]
  /// Radius spread: 0 ⇒ every circle has `radius`; > radius ⇒ each radius ~ U[radius,
  /// radius_max) from the same stream, drawn before its position (polydisperse piles).
  double radius_max = 0.0;
  /// Placement region [x0, y0, x1, y1] [m]: all zero ⇒ the Gaussian (mean, sigma); otherwise
  /// centres ~ U(region) (rejection-sampled against overlap and the walls) — tall boxes.
  std::array<double, 4> region{0.0, 0.0, 0.0, 0.0};
  /// Numbering of the generated bodies: Creation ("creation", default; the order they were
  /// placed in, random in space) or Morton ("morton": the same bodies, renumbered by the Morton
  /// code of their initial cell of side 2·max radius, so neighbours get close indices: cache
  /// locality for large piles, docs/engine.md "Step cost against size"). The random stream and the set
  /// of bodies are the same; only the indices (and so the Gauss–Seidel row order) differ.
  /// Explicit [[body]] bodies always follow in file order.
  BodyOrder order = BodyOrder::Creation;
  /// Order in which the engine stores and steps the bodies, behind their stable (external)
  /// indices: None ("none": storage order = external order), Morton ("morton": World
  /// keeps the bodies, contacts and LCP rows in the Morton order of their current cell of side
  /// 2·max radius, re-sorted when it has decayed — see resort_decay — or every `resort_every` steps at
  /// the latest; every public view stays in external order and is built only when read,
  /// docs/engine.md "Spatial body order"; circle-only scenes) or Auto ("auto", default: Morton
  /// for a world that starts with internal_order_auto_min_bodies or more bodies, all dynamic
  /// circles, none otherwise — the cache misses of large piles in creation order grow the cost
  /// per contact row with size, the translation costs more than it saves on small ones). Morton
  /// changes the Gauss–Seidel row order of the solve, hence the trajectory (to the solver's
  /// tolerance), not what users see.
  InternalOrder internal_order = InternalOrder::Auto;
  /// With the Morton internal order ("morton", or "auto" where it applies): the most steps between two re-sorts of the internal order
  /// (≥ 1; 1 = re-sort every step).
  int resort_every = 100;
  /// With the Morton internal order: re-sort at the next step when the order has decayed, i.e.
  /// when the mean |i − j| of the internal indices of the body pairs in contact reaches
  /// resort_decay times its lowest value since the last re-sort (> 1; counted in the narrow
  /// phase's loop, no extra pass). Bodies that move away from their neighbours in the
  /// order raise it; a settled pile keeps it (docs/engine.md "Step cost against size").
  double resort_decay = 1.5;

  friend bool operator==(const BodiesSection&, const BodiesSection&) = default;
};

/// One explicitly placed body (`[[body]]` in TOML), added after the generated ones.
struct BodyDef {
  Vec2 position;                 ///< centre of mass [m] (a polygon's vertices are shifted to it)
  Vec2 velocity;                 ///< [m/s]; a kinematic body's prescribed velocity
  double angle = 0.0;            ///< [rad]
  double omega = 0.0;            ///< [rad/s]; a kinematic body's prescribed angular velocity
  double radius = 1.0;           ///< circle radius; regular polygon circumradius [m]
  double density = 1.0;          ///< areal density [kg/m²]
  BodyShape shape = BodyShape::Circle;  ///< "circle" | "box" | "polygon" | "ellipse"
  Vec2 size{1.0, 1.0};           ///< box: width, height [m]
  int sides = 0;                 ///< regular polygon: number of sides (3..16); 0 = not regular
  std::vector<Vec2> vertices;    ///< explicit convex polygon, body frame, CCW [m]
  Vec2 semi_axes{1.0, 0.5};      ///< ellipse: a, b [m]
  Motion motion = Motion::Dynamic;  ///< "dynamic" | "static" | "kinematic"
  std::optional<Vec2> pivot;     ///< kinematic: rotate about this world point at omega [m]
  /// Time [s] at which the body enters the world (0 = from the start). A later body is
  /// appended (its index follows every body present before it) at the first step with
  /// t ≥ spawn at which it overlaps nothing (inflow.hpp) — e.g. the impactor of
  /// scenes/impact.toml, launched into a pile that has settled.
  double spawn = 0.0;

  friend bool operator==(const BodyDef&, const BodyDef&) = default;
};

/// Continuous inflow (`[inflow]`, inflow.hpp): circles created at `rate` per second during
/// [start, stop) at random non-overlapping positions in `region`, with `velocity`. rate = 0
/// (the default) means no inflow. The body keys mirror [bodies].
struct InflowSection {
  double rate = 0.0;                          ///< bodies per second (0 = no inflow)
  std::array<double, 4> region{0.0, 0.0, 0.0, 0.0};  ///< [x0, y0, x1, y1] of the centres [m]
  double start = 0.0;                         ///< first emission time [s]
  double stop = 0.0;                          ///< no emission at t ≥ stop [s]
  Vec2 velocity{0.0, 0.0};                    ///< initial velocity of every new body [m/s]
  double radius = 1.0;                        ///< radius [m]
  double radius_max = 0.0;                    ///< > radius ⇒ radius ~ U[radius, radius_max)
  double density = 1.0;                       ///< areal density [kg/m²]
  std::uint64_t seed = 0;                     ///< xor-ed with [bodies] seed: the placement stream
  int max_attempts = 100;                     ///< placement tries per body and step (then it waits)

  [[nodiscard]] bool active() const { return rate > 0; }
  friend bool operator==(const InflowSection&, const InflowSection&) = default;
};

/// What the bench reports about a scene family (`[family]`, docs/scenes.md "Families").
struct FamilySection {
  std::string name;   ///< family named in the bench report ("" = the scene file's stem, "seed" without a file)
  std::string seeds;  ///< evaluation seeds "A..B" / "A,B,C" the bench uses without --seeds ("" = 1..8)

  friend bool operator==(const FamilySection&, const FamilySection&) = default;
};

struct WorldDef {
  FamilySection family;
  WorldSection world;
  TimeSection time;
  ContactSection contact;
  SolverSection solver;
  BodiesSection bodies;
  InflowSection inflow;        ///< bodies added during the run (none by default)
  std::vector<BodyDef> body;   ///< explicit circles

  /// Throws ConfigError naming the first invalid key (non-finite, non-positive, ...).
  void validate() const;

  /// Field-by-field equality (tests, round trips of scene files).
  friend bool operator==(const WorldDef&, const WorldDef&) = default;
};

/// The options a scene's `[solver]` section asks for (docs/scenes.md): max_sweeps = sweeps,
/// tolerance and omega copied, every other field at its default (θ recorded, no
/// checkpoints). The one place that maps the persisted section to the solver's options.
SolverOptions solver_options(const SolverSection& solver);

/// The seed scene (identical to WorldDef{}; spelled out for readability at call sites).
inline WorldDef default_world_def() { return WorldDef{}; }

}  // namespace dc
