// The one place the oracle starters' and controls' arguments are parsed
// (oracle_starter_options.hpp): every options struct's defaults, the forms each parser
// accepts, and the forms it refuses with a one-line ConfigError naming the whole spec.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>

#include "dc/core/error.hpp"
#include "dc/research/oracle_starter_options.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "research/research_registry.hpp"
#include "warmstart/starter_error.hpp"

namespace dc {
namespace {

using test::config_error_of;
using test::expect_refused;
using test::expect_starter_error;
using test::spec;

TEST(CopyStarterOptions, DefaultsAcceptedAndRefusedForms) {
  const CopyStarterOptions d;
  EXPECT_FALSE(d.rounded);
  EXPECT_EQ(d.decimals, 0);
  EXPECT_FALSE(parse_copy_options(spec("copy")).rounded);
  for (const int dec : {0, 2, 15}) {
    const CopyStarterOptions o = parse_copy_options(spec("copy:" + std::to_string(dec)));
    EXPECT_TRUE(o.rounded);
    EXPECT_EQ(o.decimals, dec);
  }
  EXPECT_EQ(parse_copy_options(spec("copy:+3")).decimals, 3);  // std::stoi's forms stay accepted
  EXPECT_EQ(parse_copy_options(spec("copy:02")).decimals, 2);
  for (const char* bad : {"copy:16", "copy:-1", "copy:x", "copy:2.5", "copy:1e1", "copy:2:3"})
    expect_refused(parse_copy_options, bad, "copy[:D] with D an integer in 0..15");
}

TEST(CopyNoiseOptions, RIsRequiredFiniteAndNonNegative) {
  EXPECT_EQ(CopyNoiseOptions{}.relative, 0.0);
  EXPECT_EQ(parse_copy_noise_options(spec("copy-noise:0.01")).relative, 0.01);
  EXPECT_EQ(parse_copy_noise_options(spec("copy-noise:1e-2")).relative, 0.01);
  EXPECT_EQ(parse_copy_noise_options(spec("copy-noise:0")).relative, 0.0);
  EXPECT_EQ(parse_copy_noise_options(spec("copy-noise:5")).relative, 5.0);
  for (const char* bad : {"copy-noise", "copy-noise:", "copy-noise:-0.1", "copy-noise:inf", "copy-noise:nan",
                          "copy-noise:x", "copy-noise:0.1:2"})
    expect_refused(parse_copy_noise_options, bad, "copy-noise:R with R >= 0");
}

TEST(CopyActiveOptions, AShareOrAHalfOfTheActiveSet) {
  const CopyActiveOptions d;
  EXPECT_EQ(d.share, 1.0);
  EXPECT_EQ(d.part, ActiveSetPart::All);
  const CopyActiveOptions none = parse_copy_active_options(spec("copy-active"));
  EXPECT_EQ(none.share, 1.0);
  EXPECT_EQ(none.part, ActiveSetPart::All);
  EXPECT_EQ(parse_copy_active_options(spec("copy-active:0")).share, 0.0);
  EXPECT_EQ(parse_copy_active_options(spec("copy-active:0.25")).share, 0.25);
  EXPECT_EQ(parse_copy_active_options(spec("copy-active:1")).share, 1.0);
  const CopyActiveOptions normal = parse_copy_active_options(spec("copy-active:normal"));
  EXPECT_EQ(normal.part, ActiveSetPart::Normal);
  EXPECT_EQ(normal.share, 1.0);
  EXPECT_EQ(parse_copy_active_options(spec("copy-active:friction")).part, ActiveSetPart::Friction);
  for (const char* bad : {"copy-active:-0.1", "copy-active:1.5", "copy-active:x", "copy-active:0.5x",
                          "copy-active:Normal", "copy-active:nan", "copy-active:inf", "copy-active:normal:1"})
    expect_refused(parse_copy_active_options, bad, "copy-active[:F|:normal|:friction] with 0 <= F <= 1");
}

TEST(RandomStarterOptions, TheRunsSeedUnlessOneIsGiven) {
  EXPECT_FALSE(RandomStarterOptions{}.seed.has_value());
  EXPECT_FALSE(parse_random_options(spec("random")).seed.has_value());
  EXPECT_EQ(parse_random_options(spec("random:7")).seed, std::uint64_t{7});
  EXPECT_EQ(parse_random_options(spec("random:0")).seed, std::uint64_t{0});
  // std::stoull's wrap of a negative seed, accepted before the options were parsed in one place.
  EXPECT_EQ(parse_random_options(spec("random:-1")).seed, std::numeric_limits<std::uint64_t>::max());
  for (const char* bad : {"random:x", "random:7x", "random:0x10", "random:1e3", "random:18446744073709551616",
                          "random:1:2"})
    expect_refused(parse_random_options, bad, "random[:SEED] with SEED an unsigned integer");
}

TEST(OracleStarterOptions, SharedParsersNameTheOracleStarter) {
  EXPECT_EQ(parse_cgls_options(spec("copy-active-cg:20")).iterations, 20);
  expect_refused(parse_cgls_options, "copy-active-cg:x", "copy-active-cg[:ITER] with ITER >= 1");
  EXPECT_EQ(parse_sph_options(spec("sph:spiky:0.25:0.25")).kernel, SphKernelType::Spiky);
  expect_refused(parse_sph_options, "sph-gain:poly6:-1:1", "sph-gain[:KERNEL:D:H[:NORM]]");
}

TEST(OracleStarterOptions, EveryStarterRefusesAMalformedArgumentNamingTheSpec) {
  test::expect_every_starter_refuses_a_malformed_argument(test::research_registry());
}

}  // namespace
}  // namespace dc
