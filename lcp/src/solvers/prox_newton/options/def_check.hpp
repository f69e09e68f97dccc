#pragma once
// The validation of ProxNewtonDef (dc/lcp/prox_newton.hpp): every option's range, checked once
// when a solver is made so a bad setting fails with a one-line message before any solve.
#include "dc/lcp/prox_newton.hpp"

namespace dc::solvers::prox {

/// Throws InvalidArgument naming the options out of range; returns for a valid Def.
void check_def(const ProxNewtonDef& d);

}  // namespace dc::solvers::prox
