// Scene files (engine/include/dc/engine/scene.hpp): defaults, every key, every error class,
// `--set` overrides and the scene_to_toml ⇄ parse_scene round trip.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"

namespace dc {
namespace {

/// The message of the ConfigError `f` throws; fails the test if it throws nothing else.
template <class F>
std::string config_error(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a ConfigError";
  return {};
}

std::string parse_error(const std::string& text) {
  return config_error([&] { parse_scene(text, "bad.toml"); });
}

#define EXPECT_CONTAINS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << "message: " << (haystack)

// ---- defaults ---------------------------------------------------------------------------

TEST(SceneDefaults, EmptyFileIsTheSeedScene) {
  const WorldDef d = parse_scene("", "empty.toml");
  const WorldDef seed = default_world_def();
  // Section by section, so a failure says which one differs.
  EXPECT_TRUE(d.world == seed.world);
  EXPECT_TRUE(d.time == seed.time);
  EXPECT_TRUE(d.contact == seed.contact);
  EXPECT_TRUE(d.solver == seed.solver);
  EXPECT_TRUE(d.bodies == seed.bodies);
  EXPECT_TRUE(d.body.empty());
  EXPECT_TRUE(d == seed);
  // Comments and empty sections are still the seed scene.
  EXPECT_TRUE(parse_scene("# nothing\n[world]\n[time]\n[contact]\n[solver]\n[bodies]\n") == seed);
}

TEST(SceneDefaults, ShippedSceneFilesParse) {
  const std::filesystem::path dir = std::filesystem::path(DC_SOURCE_DIR) / "scenes";
  for (const char* name : {"seed.toml", "column.toml", "frictionless.toml", "small.toml"}) {
    SCOPED_TRACE(name);
    EXPECT_NO_THROW(load_scene((dir / name).string()));
  }
  EXPECT_TRUE(load_scene((dir / "seed.toml").string()) == default_world_def());
  EXPECT_EQ(load_scene((dir / "frictionless.toml").string()).contact.friction, 0.0);
  EXPECT_GT(load_scene((dir / "column.toml").string()).body.size(), 5u);
}

// ---- every key --------------------------------------------------------------------------

TEST(SceneKeys, EveryKeyIsRead) {
  const WorldDef d = parse_scene(R"(
[world]
width = 40.5
height = 20
gravity = [1.5, -3]
walls = ["bottom", "left"]
[time]
dt = 0.005
steps = 17
[contact]
friction = 0.25
restitution = 0.5
baumgarte = 0.1
slop = 0.01
margin = 0.03
restitution_threshold = 2.5
[solver]
name = "psor"
sweeps = 50
tolerance = 1e-6
omega = 1.3
[bodies]
count = 7
radius = 0.5
density = 2.0
mean = [10, 11.5]
sigma = 3.0
seed = 42
max_attempts = 99
[[body]]
position = [1, 2]
velocity = [3.5, -4]
angle = 0.7
omega = -2
radius = 0.25
density = 3
[[body]]
position = [5.0, 6.0]
)",
                                 "all.toml");
  EXPECT_EQ(d.world.width, 40.5);
  EXPECT_EQ(d.world.height, 20.0);
  EXPECT_EQ(d.world.gravity, (Vec2{1.5, -3.0}));
  EXPECT_EQ(d.world.walls, (std::array<bool, 4>{true, false, true, false}));
  EXPECT_EQ(d.time.dt, 0.005);
  EXPECT_EQ(d.time.steps, 17);
  EXPECT_EQ(d.contact.friction, 0.25);
  EXPECT_EQ(d.contact.restitution, 0.5);
  EXPECT_EQ(d.contact.baumgarte, 0.1);
  EXPECT_EQ(d.contact.slop, 0.01);
  EXPECT_EQ(d.contact.margin, 0.03);
  EXPECT_EQ(d.contact.restitution_threshold, 2.5);
  EXPECT_EQ(d.solver.name, SolverId{SolverKind::Psor});
  EXPECT_EQ(d.solver.sweeps, 50);
  EXPECT_EQ(d.solver.tolerance, 1e-6);
  EXPECT_EQ(d.solver.omega, 1.3);
  EXPECT_EQ(d.bodies.count, 7);
  EXPECT_EQ(d.bodies.radius, 0.5);
  EXPECT_EQ(d.bodies.density, 2.0);
  EXPECT_EQ(d.bodies.mean, (Vec2{10.0, 11.5}));
  EXPECT_EQ(d.bodies.sigma, 3.0);
  EXPECT_EQ(d.bodies.seed, 42u);
  EXPECT_EQ(d.bodies.max_attempts, 99);
  ASSERT_EQ(d.body.size(), 2u);
  EXPECT_EQ(d.body[0].position, (Vec2{1.0, 2.0}));
  EXPECT_EQ(d.body[0].velocity, (Vec2{3.5, -4.0}));
  EXPECT_EQ(d.body[0].angle, 0.7);
  EXPECT_EQ(d.body[0].omega, -2.0);
  EXPECT_EQ(d.body[0].radius, 0.25);
  EXPECT_EQ(d.body[0].density, 3.0);
  // Omitted body keys take BodyDef's defaults.
  BodyDef second;
  second.position = {5.0, 6.0};
  EXPECT_TRUE(d.body[1] == second);
}

TEST(SceneKeys, PartialSectionsKeepOtherDefaults) {
  const WorldDef d = parse_scene("[time]\nsteps = 5\n");
  WorldDef expected;
  expected.time.steps = 5;
  EXPECT_TRUE(d == expected);
}

TEST(SceneKeys, WallsAcceptAnySubsetIncludingNone) {
  EXPECT_EQ(parse_scene("[world]\nwalls = []\n").world.walls, (std::array<bool, 4>{false, false, false, false}));
  EXPECT_EQ(parse_scene("[world]\nwalls = [\"top\"]\n").world.walls, (std::array<bool, 4>{false, false, false, true}));
  EXPECT_EQ(parse_scene("[world]\nwalls = [\"top\", \"right\", \"left\", \"bottom\"]\n").world.walls,
            (std::array<bool, 4>{true, true, true, true}));
}

TEST(SceneKeys, LargeSeedIsAccepted) {
  EXPECT_EQ(parse_scene("[bodies]\nseed = 9223372036854775807\n").bodies.seed, 9223372036854775807ull);
  EXPECT_EQ(parse_scene("[bodies]\nseed = 0\n").bodies.seed, 0u);
}

// ---- errors -----------------------------------------------------------------------------

TEST(SceneErrors, SyntaxErrorHasLineAndColumn) {
  const std::string m = parse_error("[time]\ndt = = 3\n");
  EXPECT_CONTAINS(m, "bad.toml:2:");
  EXPECT_CONTAINS(m, "syntax");
  EXPECT_EQ(m.find('\n'), std::string::npos);
  EXPECT_CONTAINS(parse_error("[time]\ndt = 0.1\ndt = 0.2\n"), "bad.toml:3:");  // duplicate key
}

TEST(SceneErrors, UnknownSectionAndKeySuggestTheClosest) {
  std::string m = parse_error("[contact]\nfrction = 0.3\n");
  EXPECT_CONTAINS(m, "bad.toml:2:");
  EXPECT_CONTAINS(m, "[contact] frction");
  EXPECT_CONTAINS(m, "unknown key");
  EXPECT_CONTAINS(m, "'friction'");
  m = parse_error("[solvr]\nname = \"pgs\"\n");
  EXPECT_CONTAINS(m, "[solvr]");
  EXPECT_CONTAINS(m, "'solver'");
  m = parse_error("dt = 0.1\n");  // a known key outside its section
  EXPECT_CONTAINS(m, "dt");
  EXPECT_CONTAINS(m, "[time] dt");
  m = parse_error("[world]\nwidth = 3.0\n[world.sub]\nx = 1\n");
  EXPECT_CONTAINS(m, "[world] sub");
  m = parse_error("[[body]]\nposition = [1, 1]\nradus = 2\n");
  EXPECT_CONTAINS(m, "[[body]] #1 radus");
  EXPECT_CONTAINS(m, "'radius'");
}

TEST(SceneErrors, WrongTypesNameTheKey) {
  EXPECT_CONTAINS(parse_error("[time]\ndt = \"fast\"\n"), "[time] dt: expected a number, got a string");
  EXPECT_CONTAINS(parse_error("[time]\nsteps = 6.5\n"), "[time] steps: expected an integer");
  EXPECT_CONTAINS(parse_error("[time]\nsteps = 600.0\n"), "[time] steps");
  EXPECT_CONTAINS(parse_error("[solver]\nname = 3\n"), "[solver] name: expected a string");
  EXPECT_CONTAINS(parse_error("[world]\ngravity = [0.0]\n"), "[world] gravity: expected an array of 2 numbers");
  EXPECT_CONTAINS(parse_error("[world]\ngravity = 9.81\n"), "[world] gravity");
  EXPECT_CONTAINS(parse_error("[world]\ngravity = [0.0, \"down\"]\n"), "[world] gravity[1]");
  EXPECT_CONTAINS(parse_error("[bodies]\nmean = [1, 2, 3]\n"), "[bodies] mean");
  EXPECT_CONTAINS(parse_error("[world]\nwalls = \"left\"\n"), "[world] walls");
  EXPECT_CONTAINS(parse_error("[world]\nwalls = [1]\n"), "[world] walls[0]");
  EXPECT_CONTAINS(parse_error("world = 3\n"), "[world]");
  EXPECT_CONTAINS(parse_error("[contact]\nfriction = true\n"), "[contact] friction");
  EXPECT_CONTAINS(parse_error("[body]\nposition = [1, 1]\n"), "[[body]]");
  EXPECT_CONTAINS(parse_error("body = [1, 2]\n"), "[[body]] #1");
  EXPECT_CONTAINS(parse_error("[[body]]\nposition = \"here\"\n"), "[[body]] #1 position");
}

TEST(SceneErrors, WallNamesAreCheckedAndUnique) {
  std::string m = parse_error("[world]\nwalls = [\"left\", \"botom\"]\n");
  EXPECT_CONTAINS(m, "[world] walls[1]");
  EXPECT_CONTAINS(m, "'bottom'");
  m = parse_error("[world]\nwalls = [\"left\", \"left\"]\n");
  EXPECT_CONTAINS(m, "[world] walls[1]");
  EXPECT_CONTAINS(m, "twice");
}

TEST(SceneErrors, NanAndInfAreRejected) {
  EXPECT_CONTAINS(parse_error("[time]\ndt = nan\n"), "[time] dt: expected a finite number, got nan");
  EXPECT_CONTAINS(parse_error("[world]\nwidth = inf\n"), "[world] width");
  EXPECT_CONTAINS(parse_error("[world]\ngravity = [0.0, -inf]\n"), "[world] gravity[1]");
  EXPECT_CONTAINS(parse_error("[[body]]\nposition = [1, 1]\nangle = nan\n"), "[[body]] #1 angle");
  EXPECT_CONTAINS(parse_error("[solver]\ntolerance = +inf\n"), "[solver] tolerance");
}

TEST(SceneErrors, NonPositiveAndOutOfRangeValues) {
  struct Case {
    const char* text;
    const char* key;
  };
  for (const Case& c : {
           Case{"[world]\nwidth = 0\n", "[world] width"},
           Case{"[world]\nheight = -3\n", "[world] height"},
           Case{"[time]\ndt = 0.0\n", "[time] dt"},
           Case{"[time]\nsteps = -1\n", "[time] steps"},
           Case{"[contact]\nfriction = -1\n", "[contact] friction"},
           Case{"[contact]\nrestitution = 1.5\n", "[contact] restitution"},
           Case{"[solver]\nsweeps = 0\n", "[solver] sweeps"},
           Case{"[solver]\nomega = 2.0\n", "[solver] omega"},
           Case{"[bodies]\ncount = -5\n", "[bodies] count"},
           Case{"[bodies]\ncount = 10000000000\n", "[bodies] count"},
           Case{"[bodies]\nradius = 0\n", "[bodies] radius"},
           Case{"[bodies]\ndensity = -1\n", "[bodies] density"},
           Case{"[bodies]\nseed = -1\n", "[bodies] seed"},
           Case{"[[body]]\nposition = [1, 1]\n[[body]]\nposition = [4, 4]\nradius = -1\n", "[[body]] #2"},
           Case{"[[body]]\nposition = [1, 1]\ndensity = 0\n", "[[body]] #1 density"},
       }) {
    SCOPED_TRACE(c.text);
    const std::string m = parse_error(c.text);
    EXPECT_CONTAINS(m, c.key);
    EXPECT_CONTAINS(m, "bad.toml");
  }
}

TEST(SceneErrors, BodyNeedsAPosition) {
  const std::string m = parse_error("[[body]]\nposition = [1, 1]\n[[body]]\nradius = 2\n");
  EXPECT_CONTAINS(m, "[[body]] #2");
  EXPECT_CONTAINS(m, "position");
}

TEST(SceneErrors, MessagesAreOneLine) {
  for (const char* text : {"[time]\ndt = \"x\"\n", "[time\n", "x = \"\n\"\n", "[world]\nwidth = -1\n"}) {
    const std::string m = parse_error(text);
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

// ---- files ------------------------------------------------------------------------------

class SceneFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("dc_scene_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const auto p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  std::filesystem::path dir_;
};

TEST_F(SceneFiles, LoadReadsTheFileAndNamesItInErrors) {
  const std::string good = write("good.toml", "[time]\nsteps = 3\n");
  EXPECT_EQ(load_scene(good).time.steps, 3);
  const std::string bad = write("bad.toml", "[time]\nsteps = \"x\"\n");
  try {
    load_scene(bad);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_CONTAINS(e.what(), bad + ":2:");
    EXPECT_CONTAINS(e.what(), "[time] steps");
  }
}

TEST_F(SceneFiles, MissingDirectoryAndOversizedFilesAreIoErrors) {
  const std::string missing = (dir_ / "nope.toml").string();
  try {
    load_scene(missing);
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    EXPECT_CONTAINS(e.what(), missing);
  }
  EXPECT_THROW(load_scene(dir_.string()), IoError);
  const std::string big = write("big.toml", "");
  std::filesystem::resize_file(big, (16u << 20) + 1);
  EXPECT_THROW(load_scene(big), IoError);
}

// ---- overrides --------------------------------------------------------------------------

TEST(SceneOverride, SetsOneKey) {
  WorldDef d;
  apply_override(d, "time.dt=0.005");
  EXPECT_EQ(d.time.dt, 0.005);
  apply_override(d, "time.steps = 12");
  EXPECT_EQ(d.time.steps, 12);
  apply_override(d, "world.walls=[\"left\",\"bottom\"]");
  EXPECT_EQ(d.world.walls, (std::array<bool, 4>{true, false, true, false}));
  apply_override(d, "world.walls=[top]");  // quotes eaten by a shell
  EXPECT_EQ(d.world.walls, (std::array<bool, 4>{false, false, false, true}));
  apply_override(d, "solver.name=\"psor\"");
  EXPECT_EQ(d.solver.name, SolverId{SolverKind::Psor});
  apply_override(d, "solver.name=jacobi");  // bare word for string keys
  EXPECT_EQ(d.solver.name, SolverId{SolverKind::Jacobi});
  apply_override(d, "world.gravity=[0, -1.62]");
  EXPECT_EQ(d.world.gravity, (Vec2{0.0, -1.62}));
  apply_override(d, "bodies.seed=7");
  EXPECT_EQ(d.bodies.seed, 7u);
  apply_override(d, "contact.friction=0");
  EXPECT_EQ(d.contact.friction, 0.0);
  apply_override(d, "solver.omega=1.5");
  EXPECT_EQ(d.solver.omega, 1.5);
  apply_override(d, "bodies.max_attempts=10");
  EXPECT_EQ(d.bodies.max_attempts, 10);
}

TEST(SceneOverride, ErrorsNameTheAssignmentAndKey) {
  auto err = [](std::string_view a) {
    return config_error([&] {
      WorldDef d;
      apply_override(d, a);
    });
  };
  EXPECT_CONTAINS(err("time.dt"), "section.key=value");
  EXPECT_CONTAINS(err("dt=0.1"), "section.key=value");
  EXPECT_CONTAINS(err("time.dt.x=0.1"), "section.key=value");
  std::string m = err("tme.dt=0.1");
  EXPECT_CONTAINS(m, "[tme]");
  EXPECT_CONTAINS(m, "'time'");
  m = err("time.dtt=0.1");
  EXPECT_CONTAINS(m, "[time] dtt");
  EXPECT_CONTAINS(m, "'dt'");
  EXPECT_CONTAINS(err("time.dt=fast"), "[time] dt");
  EXPECT_CONTAINS(err("time.dt=\"fast\""), "[time] dt: expected a number");
  EXPECT_CONTAINS(err("time.dt=-1"), "[time] dt");
  EXPECT_CONTAINS(err("time.dt=nan"), "[time] dt");
  EXPECT_CONTAINS(err("time.dt="), "[time] dt");
  EXPECT_CONTAINS(err("time.steps=1\nother = 2"), "[time] steps");
  EXPECT_CONTAINS(err("world.walls=[\"left\",\"left\"]"), "[world] walls");
  EXPECT_CONTAINS(err("body.position=[1,2]"), "[[body]]");
  EXPECT_CONTAINS(err("time.dt=-1"), "--set time.dt=-1");
}

TEST(SceneOverride, LeavesTheDefinitionUntouchedOnError) {
  WorldDef d;
  d.time.dt = 0.02;
  EXPECT_THROW(apply_override(d, "time.dt=-1"), ConfigError);
  EXPECT_EQ(d.time.dt, 0.02);
}

// ---- writing ----------------------------------------------------------------------------

TEST(SceneRoundTrip, DefaultAndEmptyBodies) {
  const WorldDef seed;
  const std::string text = scene_to_toml(seed);
  EXPECT_TRUE(parse_scene(text, "written.toml") == seed) << text;
  // Every key is spelled out.
  for (const char* key : {"width", "height", "gravity", "walls", "dt", "steps", "friction", "restitution",
                          "baumgarte", "slop", "margin", "restitution_threshold", "name", "sweeps", "tolerance",
                          "omega", "count", "radius", "density", "mean", "sigma", "seed", "max_attempts"}) {
    EXPECT_CONTAINS(text, std::string("\n") + key + " = ");
  }
}

TEST(SceneRoundTrip, AwkwardValuesSurviveBitExactly) {
  WorldDef d;
  d.world.width = 0.1 + 0.2;  // not the shortest-looking decimal
  d.world.height = 1e300;
  d.world.gravity = {-0.0, -9.80665};
  d.world.walls = {false, true, false, true};
  d.time.dt = 1.0 / 3.0;
  d.time.steps = 0;
  d.contact.friction = 0.0;
  d.contact.restitution = std::nextafter(1.0, 0.0);
  d.contact.slop = 5e-324;  // smallest subnormal
  d.family.name = "we\"ird\\name\t";
  d.solver.name = SolverId{SolverKind::PgsColored, 3, PgsColoredKernel::Scalar};
  d.solver.tolerance = 123456789.125;
  d.solver.sweeps = std::numeric_limits<int>::max();
  d.bodies.count = 0;
  d.bodies.seed = 9223372036854775807ull;
  d.bodies.mean = {1e-7, 2.5e10};
  for (int i = 0; i < 3; ++i) {
    BodyDef b;
    b.position = {1.0 / (i + 3), 2.0 + i};
    b.velocity = {std::sqrt(2.0) * i, -std::acos(-1.0)};
    b.angle = 0.1 * i;
    b.omega = -1e-3 * i;
    b.radius = 0.5 + i;
    b.density = 7.0 / 9.0;
    d.body.push_back(b);
  }
  const std::string text = scene_to_toml(d);
  const WorldDef back = parse_scene(text, "written.toml");
  EXPECT_TRUE(back == d) << text;
  EXPECT_TRUE(std::signbit(back.world.gravity.x));
  // Writing is a fixed point.
  EXPECT_EQ(scene_to_toml(back), text);
}

TEST(SceneRoundTrip, UnwritableSeedIsAnError) {
  WorldDef d;
  d.bodies.seed = std::numeric_limits<std::uint64_t>::max();
  EXPECT_CONTAINS(config_error([&] { scene_to_toml(d); }), "[bodies] seed");
}

// ---- named values (typed in WorldDef, strings in files) ------------------------------------

/// Sets `key=value` by --set, writes the scene and reads it back: the definition survives and
/// the file spells the value as given.
WorldDef set_and_round_trip(WorldDef d, const std::string& key, const std::string& value) {
  apply_override(d, key + "=" + value);
  const std::string text = scene_to_toml(d);
  EXPECT_CONTAINS(text, key.substr(key.find('.') + 1) + " = \"" + value + "\"");
  const WorldDef back = parse_scene(text, "written.toml");
  EXPECT_TRUE(back == d) << text;
  return back;
}

TEST(SceneNames, EverySpellingRoundTrips) {
  WorldDef d;
  d.bodies.sides = 5;  // lets shape = "polygon" validate (ignored by the other shapes)
  for (BodyShape s : {BodyShape::Circle, BodyShape::Box, BodyShape::Polygon, BodyShape::Ellipse}) {
    EXPECT_EQ(parse_body_shape(to_string(s), "k"), s);
    EXPECT_EQ(set_and_round_trip(d, "bodies.shape", to_string(s)).bodies.shape, s);
  }
  for (BodyOrder o : {BodyOrder::Creation, BodyOrder::Morton}) {
    EXPECT_EQ(parse_body_order(to_string(o), "k"), o);
    EXPECT_EQ(set_and_round_trip(d, "bodies.order", to_string(o)).bodies.order, o);
  }
  for (InternalOrder o : {InternalOrder::None, InternalOrder::Morton, InternalOrder::Auto}) {
    EXPECT_EQ(parse_internal_order(to_string(o), "k"), o);
    EXPECT_EQ(set_and_round_trip(d, "bodies.internal_order", to_string(o)).bodies.internal_order, o);
  }
  std::vector<std::string> solvers = solver_names();
  solvers.insert(solvers.end(), {"pgs-colored:2", "pgs-colored:4:scalar", "pgs-colored:1:avx512"});
  for (const std::string& name : solvers)
    EXPECT_EQ(to_string(set_and_round_trip(d, "solver.name", name).solver.name), name);
  for (Motion m : {Motion::Dynamic, Motion::Static, Motion::Kinematic}) {
    EXPECT_EQ(parse_motion(motion_name(m), "k"), m);
    const std::string text =
        std::string("[[body]]\nposition = [5.0, 5.0]\nmotion = \"") + motion_name(m) + "\"\n";
    const WorldDef w = parse_scene(text);
    ASSERT_EQ(w.body.size(), 1u);
    EXPECT_EQ(w.body[0].motion, m);
    EXPECT_CONTAINS(scene_to_toml(w), std::string("motion = \"") + motion_name(m) + "\"");
    EXPECT_TRUE(parse_scene(scene_to_toml(w)) == w);
  }
}

TEST(SceneNames, UnknownSpellingsGiveOneLineErrorsNamingTheKey) {
  const std::string shapes = "(expected circle, box, polygon or ellipse)";
  EXPECT_EQ(parse_error("[bodies]\nshape = \"hexagon\"\n"),
            "bad.toml: [bodies] shape: unknown shape 'hexagon' " + shapes);
  EXPECT_EQ(parse_error("[[body]]\nposition = [1.0, 1.0]\nshape = \"hexagon\"\n"),
            "bad.toml: [[body]] #1 shape: unknown shape 'hexagon' " + shapes);
  EXPECT_EQ(parse_error("[[body]]\nposition = [1.0, 1.0]\nmotion = \"moving\"\n"),
            "bad.toml: [[body]] #1 motion: unknown motion 'moving' (expected dynamic, static or kinematic)");
  EXPECT_EQ(parse_error("[bodies]\norder = \"hilbert\"\n"),
            "bad.toml: [bodies] order: expected \"creation\" or \"morton\", got \"hilbert\"");
  EXPECT_EQ(parse_error("[bodies]\ninternal_order = \"hilbert\"\n"),
            "bad.toml: [bodies] internal_order: expected \"none\", \"morton\" or \"auto\", got \"hilbert\"");
  const std::string unknown_solver = config_error([] { (void)SolverId::parse("gauss"); });
  EXPECT_EQ(parse_error("[solver]\nname = \"gauss\"\n"), unknown_solver);  // make_solver's message, as always
  WorldDef d;
  EXPECT_EQ(config_error([&] { apply_override(d, "bodies.order=hilbert"); }),
            "--set bodies.order=hilbert: [bodies] order: expected \"creation\" or \"morton\", got \"hilbert\"");
  EXPECT_EQ(config_error([&] { apply_override(d, "solver.name=pgs-colored:0"); }),
            config_error([] { (void)SolverId::parse("pgs-colored:0"); }));
  EXPECT_TRUE(d == WorldDef{});
}

}  // namespace
}  // namespace dc

namespace dc {
namespace {

// `--scene hopper` and World(scene="hopper"): a name without '/' that is not a file reads the
// shipped scene of that name (dc::data_path, here the build tree's share/deepcontact).
TEST(ShippedScenes, ANameReadsTheShippedFile) {
  const WorldDef by_path = load_scene(std::string(DC_SOURCE_DIR) + "/scenes/column.toml");
  EXPECT_EQ(load_scene("column"), by_path);
  EXPECT_EQ(load_scene("column.toml"), by_path);
  const auto names = shipped_scenes();
  EXPECT_NE(std::find(names.begin(), names.end(), "hopper"), names.end());
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
}

TEST(ShippedScenes, AnUnknownNameListsTheShippedScenes) {
  try {
    (void)load_scene("no-such-scene");
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no-such-scene: cannot read scene file: no such file"), std::string::npos) << what;
    EXPECT_NE(what.find("column"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace dc
