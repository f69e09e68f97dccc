// The scene key table. Docs strings are the comments of world_def.hpp, shortened; they
// are written next to each key by scene_to_toml() (docs/scenes.md has the long form).
#include "world/scene_keys.hpp"

namespace dc::scene_detail {
namespace {
using Walls = std::array<bool, 4>;
using Region = std::array<double, 4>;
}  // namespace

// The unary + turns each captureless lambda into the function pointer the variant holds.
#define DC_FIELD(T, Owner, member) +[](Owner & d) -> T& { return d.member; }

std::span<const SectionKey> section_keys() {
  static const SectionKey keys[] = {
      {"family", "name", Kind::String, DC_FIELD(std::string, WorldDef, family.name),
       "family named in bench reports (\"\" = the scene file's stem)"},
      {"family", "seeds", Kind::String, DC_FIELD(std::string, WorldDef, family.seeds),
       "evaluation seeds of bench without --seeds, e.g. \"1..4\" (\"\" = 1..8)"},
      {"world", "width", Kind::Number, DC_FIELD(double, WorldDef, world.width), "box extent along x [m]"},
      {"world", "height", Kind::Number, DC_FIELD(double, WorldDef, world.height), "box extent along y [m]"},
      {"world", "gravity", Kind::Vec2, DC_FIELD(Vec2, WorldDef, world.gravity), "gravitational acceleration [m/s^2]"},
      {"world", "walls", Kind::Walls, DC_FIELD(Walls, WorldDef, world.walls),
       "any of left (x=0), right (x=width), bottom (y=0), top (y=height)"},
      {"time", "dt", Kind::Number, DC_FIELD(double, WorldDef, time.dt), "time step [s]"},
      {"time", "steps", Kind::Int, DC_FIELD(int, WorldDef, time.steps), "number of steps a simulation runs"},
      {"contact", "friction", Kind::Number, DC_FIELD(double, WorldDef, contact.friction),
       "Coulomb coefficient mu (0 = no tangent rows)"},
      {"contact", "restitution", Kind::Number, DC_FIELD(double, WorldDef, contact.restitution),
       "e in [0, 1]: separating normal velocity -e*v_n"},
      {"contact", "baumgarte", Kind::Number, DC_FIELD(double, WorldDef, contact.baumgarte),
       "beta in [0, 1]: fraction of penetration beyond slop removed per step"},
      {"contact", "slop", Kind::Number, DC_FIELD(double, WorldDef, contact.slop),
       "allowed penetration before Baumgarte acts [m]"},
      {"contact", "margin", Kind::Number, DC_FIELD(double, WorldDef, contact.margin),
       "speculative contact margin [m]"},
      {"contact", "restitution_threshold", Kind::Number, DC_FIELD(double, WorldDef, contact.restitution_threshold),
       "approach speed below which restitution is ignored [m/s]"},
      {"solver", "name", Kind::String, DC_FIELD(SolverId, WorldDef, solver.name),
       "pgs-colored[:threads] (default), pgs, pgs-assembled, psor, jacobi, lemke, newton"},
      {"solver", "sweeps", Kind::Int, DC_FIELD(int, WorldDef, solver.sweeps), "maximum sweeps per step (>= 1)"},
      {"solver", "tolerance", Kind::Number, DC_FIELD(double, WorldDef, solver.tolerance),
       "stop when theta_k <= tolerance [N]; 0 = always run all sweeps"},
      {"solver", "omega", Kind::Number, DC_FIELD(double, WorldDef, solver.omega),
       "relaxation in (0, 2) for psor (1 = PGS)"},
      {"solver", "relax_sweeps", Kind::Int, DC_FIELD(int, WorldDef, solver.relax_sweeps),
       "sweeps of the bias-free relax pass after each solve (0 = none)"},
      {"bodies", "count", Kind::Int, DC_FIELD(int, WorldDef, bodies.count), "generated circles (0 = none)"},
      {"bodies", "radius", Kind::Number, DC_FIELD(double, WorldDef, bodies.radius), "radius of generated circles [m]"},
      {"bodies", "density", Kind::Number, DC_FIELD(double, WorldDef, bodies.density), "areal density [kg/m^2]"},
      {"bodies", "mean", Kind::Vec2, DC_FIELD(Vec2, WorldDef, bodies.mean),
       "mean of the 2D Gaussian of initial centres [m]"},
      {"bodies", "sigma", Kind::Number, DC_FIELD(double, WorldDef, bodies.sigma),
       "standard deviation per axis [m] (seed: 1.2*sqrt(15))"},
      {"bodies", "seed", Kind::Seed, DC_FIELD(std::uint64_t, WorldDef, bodies.seed),
       "seed of the GSL mt19937 stream that places them"},
      {"bodies", "max_attempts", Kind::Int, DC_FIELD(int, WorldDef, bodies.max_attempts),
       "rejection-sampling budget before giving up (error)"},
      {"bodies", "shape", Kind::String, DC_FIELD(BodyShape, WorldDef, bodies.shape),
       "circle, box, polygon or ellipse (non-circles get a random angle)"},
      {"bodies", "size", Kind::Vec2, DC_FIELD(Vec2, WorldDef, bodies.size), "box: width, height [m]"},
      {"bodies", "sides", Kind::Int, DC_FIELD(int, WorldDef, bodies.sides),
       "regular polygon: sides 3..16 (circumradius = radius); 0 = use vertices"},
      {"bodies", "vertices", Kind::Points, DC_FIELD(std::vector<Vec2>, WorldDef, bodies.vertices),
       "polygon: convex, counter-clockwise [[x, y], ...] [m]"},
      {"bodies", "semi_axes", Kind::Vec2, DC_FIELD(Vec2, WorldDef, bodies.semi_axes), "ellipse: a, b [m]"},
      {"bodies", "radius_max", Kind::Number, DC_FIELD(double, WorldDef, bodies.radius_max),
       "0 = all circles have radius; > radius: radius ~ U[radius, radius_max) [m]"},
      {"bodies", "region", Kind::Region, DC_FIELD(Region, WorldDef, bodies.region),
       "[x0, y0, x1, y1]: centres ~ U(region) instead of the Gaussian; all 0 = unset [m]"},
      {"bodies", "order", Kind::String, DC_FIELD(BodyOrder, WorldDef, bodies.order),
       "numbering of generated bodies: creation (placement order) or morton (spatial, for cache locality)"},
      {"bodies", "internal_order", Kind::String, DC_FIELD(InternalOrder, WorldDef, bodies.internal_order),
       "engine-internal storage order behind stable indices: none, morton (re-sorted, circle-only) or auto (morton from 20000 circles)"},
      {"bodies", "resort_every", Kind::Int, DC_FIELD(int, WorldDef, bodies.resort_every),
       "internal Morton order: most steps between re-sorts (>= 1)"},
      {"bodies", "resort_decay", Kind::Number, DC_FIELD(double, WorldDef, bodies.resort_decay),
       "internal Morton order: re-sort when the mean |i - j| of the pairs in contact grows by this factor over its lowest (> 1)"},
      {"inflow", "rate", Kind::Number, DC_FIELD(double, WorldDef, inflow.rate), "bodies per second (0 = no inflow)"},
      {"inflow", "region", Kind::Region, DC_FIELD(Region, WorldDef, inflow.region),
       "[x0, y0, x1, y1] where new centres are placed [m]"},
      {"inflow", "start", Kind::Number, DC_FIELD(double, WorldDef, inflow.start), "first emission time [s]"},
      {"inflow", "stop", Kind::Number, DC_FIELD(double, WorldDef, inflow.stop), "no emission from this time on [s]"},
      {"inflow", "velocity", Kind::Vec2, DC_FIELD(Vec2, WorldDef, inflow.velocity),
       "initial velocity of new bodies [m/s]"},
      {"inflow", "radius", Kind::Number, DC_FIELD(double, WorldDef, inflow.radius), "radius of new circles [m]"},
      {"inflow", "radius_max", Kind::Number, DC_FIELD(double, WorldDef, inflow.radius_max),
       "0 = all have radius; > radius: radius ~ U[radius, radius_max) [m]"},
      {"inflow", "density", Kind::Number, DC_FIELD(double, WorldDef, inflow.density), "areal density [kg/m^2]"},
      {"inflow", "seed", Kind::Seed, DC_FIELD(std::uint64_t, WorldDef, inflow.seed),
       "xor-ed with [bodies] seed: seed of the placement stream"},
      {"inflow", "max_attempts", Kind::Int, DC_FIELD(int, WorldDef, inflow.max_attempts),
       "placement tries per body and step (a body that finds no room waits)"},
  };
  return keys;
}

std::span<const BodyKey> body_keys() {
  static const BodyKey keys[] = {
      {"position", Kind::Vec2, DC_FIELD(Vec2, BodyDef, position)},
      {"velocity", Kind::Vec2, DC_FIELD(Vec2, BodyDef, velocity)},
      {"angle", Kind::Number, DC_FIELD(double, BodyDef, angle)},
      {"omega", Kind::Number, DC_FIELD(double, BodyDef, omega)},
      {"radius", Kind::Number, DC_FIELD(double, BodyDef, radius)},
      {"density", Kind::Number, DC_FIELD(double, BodyDef, density)},
      {"shape", Kind::String, DC_FIELD(BodyShape, BodyDef, shape)},
      {"size", Kind::Vec2, DC_FIELD(Vec2, BodyDef, size)},
      {"sides", Kind::Int, DC_FIELD(int, BodyDef, sides)},
      {"vertices", Kind::Points, DC_FIELD(std::vector<Vec2>, BodyDef, vertices)},
      {"semi_axes", Kind::Vec2, DC_FIELD(Vec2, BodyDef, semi_axes)},
      {"motion", Kind::String, DC_FIELD(Motion, BodyDef, motion)},
      {"pivot", Kind::OptionalVec2, DC_FIELD(std::optional<Vec2>, BodyDef, pivot)},
      {"spawn", Kind::Number, DC_FIELD(double, BodyDef, spawn)},
  };
  return keys;
}

#undef DC_FIELD

const std::array<std::string_view, 4>& wall_names() {
  static const std::array<std::string_view, 4> names{"left", "right", "bottom", "top"};
  return names;
}

}  // namespace dc::scene_detail
