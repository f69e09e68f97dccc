// sph-residual (builtin + the grid read-back of λ* − builtin: the oracle bound of a residual
// grid predictor) and gate:INNER (per step INNER's guess or builtin's, whichever has the
// smaller natural-map residual).
#include <gtest/gtest.h>

#include <cmath>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "floor_discs.hpp"

namespace dc {
namespace {

using test::discs_on_floor;
using test::step_with;

TEST(GateWarmStart, BadSpecificationsAreOneLineErrors) {
  const WarmStarterRegistry r = default_warm_starters();
  EXPECT_THROW(r.make("gate"), ConfigError);                // nothing to gate
  EXPECT_THROW(r.make("gate:gate:builtin"), ConfigError);   // no gate of a gate
  EXPECT_THROW(r.make("gate-l2:nonsense"), ConfigError);    // unknown inner starter
  EXPECT_THROW(r.make("gate:builtin-coarse:x"), ConfigError);  // the inner's own argument check
  EXPECT_NO_THROW(r.make("gate:builtin-statics"));
}

}  // namespace
}  // namespace dc
