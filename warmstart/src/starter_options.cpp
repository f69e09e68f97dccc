#include "dc/warmstart/starter_options.hpp"

#include "dc/core/error.hpp"
#include "dc/sph/sph_setting.hpp"

namespace dc {

CoarseStarterOptions parse_coarse_options(const WarmStartSpec& spec) {
  const StarterArgument arg(spec, spec.name + "[:D[:ITER]] with D > 0 [m] and ITER >= 1");
  CoarseStarterOptions o;
  const auto f = arg.fields(0, 2);
  if (f.size() >= 1) o.spacing = arg.positive_number(f[0]);
  if (f.size() >= 2) o.iterations = arg.integer(f[1], 1);
  return o;
}

CglsStarterOptions parse_cgls_options(const WarmStartSpec& spec) {
  const StarterArgument arg(spec, spec.name + "[:ITER] with ITER >= 1");
  CglsStarterOptions o;
  const auto f = arg.fields(0, 1);
  if (!f.empty()) o.iterations = arg.integer(f[0], 1);
  return o;
}

GateOptions parse_gate_options(const WarmStartSpec& spec) {
  GateOptions o;
  if (spec.name == "gate-l2") o.norm = GateNorm::L2;
  else if (spec.name != "gate") throw InvalidArgument("parse_gate_options: '" + spec.name + "' is not gate or gate-l2");
  const StarterArgument arg(spec, spec.name + ":INNER with INNER any starter but a gate, e.g. " + spec.name +
                                      ":cnn:models/impact.h5");
  if (arg.empty()) arg.fail();
  const std::string inner_name = arg.text().substr(0, arg.text().find(':'));
  if (inner_name.empty()) arg.fail();
  if (inner_name == "gate" || inner_name == "gate-l2") arg.fail("a gate cannot gate another gate");
  o.inner = arg.text();
  return o;
}

SphTransferDef parse_sph_options(const WarmStartSpec& spec) {
  SphTransferDef def = default_sph_setting(30.0, 30.0);  // box replaced by the scene's
  try {
    parse_sph_setting(spec.arg, def);
  } catch (const ConfigError& e) {
    StarterArgument(spec, spec.name + "[:KERNEL:D:H[:NORM]] with D, H > 0 [m]").fail(e.what());
  }
  return def;
}

}  // namespace dc
