// The one place the methods' arguments are parsed (starter_argument.hpp, starter_options.hpp):
// every options struct's defaults, the forms each parser accepts, and the forms it refuses
// with a one-line ConfigError naming the whole spec.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/sph/sph_setting.hpp"
#include "dc/warmstart/starter_argument.hpp"
#include "dc/warmstart/starter_options.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "warmstart/starter_error.hpp"

namespace dc {
namespace {

using test::config_error_of;
using test::expect_refused;
using test::expect_starter_error;
using test::spec;

TEST(StarterArgument, SplitsTheArgumentIntoFieldsKeepingEmptyOnes) {
  const StarterArgument none(spec("x"), "x[:A[:B]]");
  EXPECT_TRUE(none.empty());
  EXPECT_TRUE(none.fields(0, 2).empty());
  EXPECT_EQ(StarterArgument(spec("x:a"), "u").fields(0, 2), (std::vector<std::string>{"a"}));
  EXPECT_EQ(StarterArgument(spec("x:a:b"), "u").fields(0, 2), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(StarterArgument(spec("x:1:"), "u").fields(0, 2), (std::vector<std::string>{"1", ""}));
  EXPECT_EQ(StarterArgument(spec("x::"), "u").fields(0, 2), (std::vector<std::string>{"", ""}));
  // Too few or too many fields: the uniform message.
  expect_starter_error(config_error_of([] { (void)StarterArgument(spec("x"), "x:A").fields(1, 1); }), "x", "x:A");
  expect_starter_error(config_error_of([] { (void)StarterArgument(spec("x:1:2:3"), "x[:A[:B]]").fields(0, 2); }),
                       "x:1:2:3", "x[:A[:B]]");
}

TEST(StarterArgument, IntegersFollowStoiAndTheRange) {
  const StarterArgument a(spec("n:7"), "n[:K] with K in 0..15");
  EXPECT_EQ(a.integer("7", 0, 15), 7);
  EXPECT_EQ(a.integer("+3", 0, 15), 3);   // accepted before the options were parsed in one place
  EXPECT_EQ(a.integer(" 3", 0, 15), 3);   // std::stoi skips leading white space
  EXPECT_EQ(a.integer("007", 0, 15), 7);
  EXPECT_EQ(a.integer("-0", 0, 15), 0);
  EXPECT_EQ(a.integer("2147483647", 1), std::numeric_limits<int>::max());
  for (const char* bad : {"", "x", "3.0", "1e1", "3 ", "0x10", "16", "-1", "2147483648", "99999999999"})
    expect_starter_error(config_error_of([&] { (void)a.integer(bad, 0, 15); }), "n:7", "n[:K] with K in 0..15");
}

TEST(StarterArgument, NumbersAreFiniteAndInTheirRange) {
  const StarterArgument a(spec("d:1"), "d[:D] with D > 0");
  EXPECT_EQ(a.positive_number("0.5"), 0.5);
  EXPECT_EQ(a.positive_number(".5"), 0.5);
  EXPECT_EQ(a.positive_number("1e-1"), 0.1);
  EXPECT_EQ(a.positive_number("0x1p0"), 1.0);  // std::stod reads hexadecimal floats
  for (const char* bad : {"", "0", "-0", "-1", "x", "1x", "inf", "nan", "1e400", "1e-400"})
    expect_starter_error(config_error_of([&] { (void)a.positive_number(bad); }), "d:1", "d[:D] with D > 0");

  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(a.number("0", 0.0, 1.0), 0.0);
  EXPECT_EQ(a.number("1", 0.0, 1.0), 1.0);
  EXPECT_EQ(a.number("1e0", 0.0, 1.0), 1.0);
  EXPECT_EQ(a.number("-0", 0.0, inf), 0.0);
  EXPECT_EQ(a.number("5", 0.0, inf), 5.0);
  for (const char* bad : {"-0.1", "1.5", "nan", "inf", "0.5x", ""})
    EXPECT_THROW((void)a.number(bad, 0.0, 1.0), ConfigError) << bad;
  EXPECT_THROW((void)a.number("inf", 0.0, inf), ConfigError);  // finite even when hi is +inf
}

TEST(StarterArgument, UnsignedIntegersFollowStoull) {
  const StarterArgument a(spec("r:1"), "r[:SEED]");
  EXPECT_EQ(a.unsigned_integer("7"), 7u);
  EXPECT_EQ(a.unsigned_integer("18446744073709551615"), std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(a.unsigned_integer("-1"), std::numeric_limits<std::uint64_t>::max());  // std::stoull wraps
  for (const char* bad : {"", "x", "7x", "0x10", "1e3", "18446744073709551616"})
    EXPECT_THROW((void)a.unsigned_integer(bad), ConfigError) << bad;
}

TEST(StarterArgument, FailAppendsAReasonOnTheSameLine) {
  const std::string m = config_error_of([] { StarterArgument(spec("s:q"), "s[:K]").fail("unknown K 'q'"); });
  EXPECT_EQ(m, "warm starter 's:q': expected s[:K] (unknown K 'q')");
}

TEST(StarterArgument, StartersWithoutOptionsRefuseAnyArgument) {
  EXPECT_NO_THROW(reject_argument(spec("zero")));
  EXPECT_NO_THROW(reject_argument(spec("zero:")));  // an empty argument is no argument
  for (const char* bad : {"zero:1", "builtin:x", "builtin-active:1"})
    expect_refused([](const WarmStartSpec& s) { reject_argument(s); return 0; }, bad, "without an argument");
}

TEST(CoarseStarterOptions, DefaultsAndAcceptedForms) {
  const CoarseStarterOptions d;
  EXPECT_EQ(d.spacing, 1.0);
  EXPECT_EQ(d.iterations, 30);
  const CoarseStarterOptions none = parse_coarse_options(spec("builtin-coarse"));
  EXPECT_EQ(none.spacing, d.spacing);
  EXPECT_EQ(none.iterations, d.iterations);
  const CoarseStarterOptions only_d = parse_coarse_options(spec("builtin-coarse:0.5"));
  EXPECT_EQ(only_d.spacing, 0.5);
  EXPECT_EQ(only_d.iterations, 30);
  const CoarseStarterOptions both = parse_coarse_options(spec("builtin-coarse:2:10"));
  EXPECT_EQ(both.spacing, 2.0);
  EXPECT_EQ(both.iterations, 10);
}

TEST(CoarseStarterOptions, RefusedForms) {
  for (const char* bad : {"builtin-coarse:0", "builtin-coarse:-1", "builtin-coarse:x", "builtin-coarse:1:0",
                          "builtin-coarse:1:2:3", "builtin-coarse:1x", "builtin-coarse:inf", "builtin-coarse:nan",
                          "builtin-coarse:1:", "builtin-coarse::30", "builtin-coarse:1:30.5"})
    expect_refused(parse_coarse_options, bad, "builtin-coarse[:D[:ITER]] with D > 0 [m] and ITER >= 1");
}

TEST(CglsStarterOptions, DefaultsAcceptedAndRefusedForms) {
  EXPECT_EQ(CglsStarterOptions{}.iterations, 100);
  EXPECT_EQ(parse_cgls_options(spec("builtin-active-cg")).iterations, 100);
  EXPECT_EQ(parse_cgls_options(spec("builtin-active-cg:1")).iterations, 1);
  EXPECT_EQ(parse_cgls_options(spec("builtin-active-cg:3000")).iterations, 3000);
  for (const char* bad : {"builtin-active-cg:0", "builtin-active-cg:-3", "builtin-active-cg:x",
                          "builtin-active-cg:5.0", "builtin-active-cg:5:5", "builtin-active-cg:99999999999"})
    expect_refused(parse_cgls_options, bad, "builtin-active-cg[:ITER] with ITER >= 1");
  // The message names the starter it was parsed for (copy-active-cg shares the parser).
  expect_refused(parse_cgls_options, "copy-active-cg:0", "copy-active-cg[:ITER] with ITER >= 1");
}

TEST(GateOptions, DefaultsAcceptedAndRefusedForms) {
  const GateOptions d;
  EXPECT_TRUE(d.inner.empty());
  EXPECT_EQ(d.norm, GateNorm::Max);
  const GateOptions g = parse_gate_options(spec("gate:builtin"));
  EXPECT_EQ(g.inner, "builtin");
  EXPECT_EQ(g.norm, GateNorm::Max);
  // The inner spec is kept whole, its own ':' included; the norm is in the name.
  const GateOptions l2 = parse_gate_options(spec("gate-l2:cnn:models/impact.h5"));
  EXPECT_EQ(l2.inner, "cnn:models/impact.h5");
  EXPECT_EQ(l2.norm, GateNorm::L2);
  for (const char* bad : {"gate", "gate:", "gate::x", "gate:gate:builtin", "gate:gate-l2:builtin", "gate:gate"})
    expect_refused(parse_gate_options, bad, "gate:INNER");
  expect_refused(parse_gate_options, "gate-l2:gate", "gate-l2:INNER");
  // Another name is a programming error, not a user's.
  EXPECT_THROW((void)parse_gate_options(spec("copy:builtin")), InvalidArgument);
}

TEST(SphStarterOptions, DefaultIsTheBenchSettingAndTheArgumentOverridesIt) {
  const SphTransferDef d = default_sph_setting(30.0, 30.0);
  const SphTransferDef none = parse_sph_options(spec("sph-prev"));
  EXPECT_EQ(none.kernel, d.kernel);
  EXPECT_EQ(none.grid.spacing, d.grid.spacing);
  EXPECT_EQ(none.support, d.support);
  EXPECT_EQ(none.normalisation, d.normalisation);
  EXPECT_EQ(none.kernel, SphKernelType::Poly6);
  EXPECT_EQ(none.grid.spacing, 0.5);
  EXPECT_EQ(none.support, 0.355);
  EXPECT_EQ(none.normalisation, SphNormalisation::Shepard);

  const SphTransferDef s = parse_sph_options(spec("sph-prev:spiky:0.25:0.3"));
  EXPECT_EQ(s.kernel, SphKernelType::Spiky);
  EXPECT_EQ(s.grid.spacing, 0.25);
  EXPECT_EQ(s.support, 0.3);
  EXPECT_EQ(s.normalisation, SphNormalisation::Shepard);
  EXPECT_EQ(parse_sph_options(spec("builtin-gain-extrapolate:poly6:0.5:0.5:legacy")).normalisation,
            SphNormalisation::SumToOneLegacy);
  EXPECT_EQ(parse_sph_options(spec("sph-prev:poly6:0.5:0.5:none")).normalisation, SphNormalisation::None);
}

TEST(SphStarterOptions, RefusedFormsNameTheSpecAndTheBadPart) {
  const std::string usage = "sph-prev[:KERNEL:D:H[:NORM]] with D, H > 0 [m]";
  for (const auto& [bad, part] : std::vector<std::pair<std::string, std::string>>{
           {"sph-prev:poly6:0:1", "D must be"},
           {"sph-prev:poly6:0.5:-1", "H must be"},
           {"sph-prev:poly6:0.5:inf", "H must be"},
           {"sph-prev:poly6", "KERNEL:D:H"},
           {"sph-prev:poly6:0.5:0.5:shepard:1", "KERNEL:D:H"},
           {"sph-prev:foo:0.5:0.5", "unknown sph kernel 'foo'"},
           {"sph-prev:poly6:0.5:0.5:bogus", "unknown sph normalisation 'bogus'"}}) {
    const std::string m = config_error_of([&] { (void)parse_sph_options(spec(bad)); });
    expect_starter_error(m, bad, usage);
    EXPECT_NE(m.find(part), std::string::npos) << m;
  }
}

TEST(StarterOptions, EveryMethodRefusesAMalformedArgumentNamingTheSpec) {
  test::expect_every_starter_refuses_a_malformed_argument(default_warm_starters());
}

}  // namespace
}  // namespace dc
