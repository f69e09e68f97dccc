#include "dc/research/oracle_starter_options.hpp"

#include <limits>

#include "dc/warmstart/starter_argument.hpp"

namespace dc {

CopyStarterOptions parse_copy_options(const WarmStartSpec& spec) {
  const StarterArgument arg(spec, spec.name + "[:D] with D an integer in 0..15");
  CopyStarterOptions o;
  const auto f = arg.fields(0, 1);
  if (!f.empty()) {
    o.rounded = true;
    o.decimals = arg.integer(f[0], 0, 15);
  }
  return o;
}

CopyNoiseOptions parse_copy_noise_options(const WarmStartSpec& spec) {
  const StarterArgument arg(spec, spec.name + ":R with R >= 0, e.g. " + spec.name + ":0.01");
  CopyNoiseOptions o;
  o.relative = arg.number(arg.fields(1, 1)[0], 0.0, std::numeric_limits<double>::infinity());
  return o;
}

CopyActiveOptions parse_copy_active_options(const WarmStartSpec& spec) {
  const StarterArgument arg(spec, spec.name + "[:F|:normal|:friction] with 0 <= F <= 1");
  CopyActiveOptions o;
  const auto f = arg.fields(0, 1);
  if (f.empty()) return o;
  if (f[0] == "normal") o.part = ActiveSetPart::Normal;
  else if (f[0] == "friction") o.part = ActiveSetPart::Friction;
  else o.share = arg.number(f[0], 0.0, 1.0);
  return o;
}

RandomStarterOptions parse_random_options(const WarmStartSpec& spec) {
  const StarterArgument arg(spec, spec.name + "[:SEED] with SEED an unsigned integer");
  RandomStarterOptions o;
  const auto f = arg.fields(0, 1);
  if (!f.empty()) o.seed = arg.unsigned_integer(f[0]);
  return o;
}

}  // namespace dc
