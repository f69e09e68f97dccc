#pragma once
// What a candidate λ would do to the world if the step were integrated with it, without
// touching the world: the penetration of this step's contacts and the total energy after
// the step. Used for the penetration/energy axes of the speed/accuracy trade.
#include <Eigen/Core>

#include "dc/engine/world.hpp"

namespace dc::bench {

struct StepOutcome {
  double penetration = 0;  ///< max(0, −min gap) over this step's contact pairs after the step [m]
  double energy = 0;       ///< kinetic + potential energy after the step [J]
};

/// Evaluates λ on the world's current (collided, assembled) step. `scratch` avoids allocation.
StepOutcome evaluate_step(const World& world, const Eigen::VectorXd& lambda, Eigen::VectorXd& scratch);

}  // namespace dc::bench
