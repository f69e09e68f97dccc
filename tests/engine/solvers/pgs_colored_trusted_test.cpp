// The engine's own problems skip pgs-colored's structural checks: assemble_lcp stamps the
// problem it builds (StructureStamp), and the solver then checks only b and λ⁰ finite (counted
// in PgsColoredProfile::structure_trusted). A copy of it, intact or edited, is checked whole and a
// broken one rejected with LcpProblem::validate's message.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dc/core/error.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"

namespace dc {
namespace {

/// A settling pile of `bodies` circles, bodies stored in `order`.
WorldDef trusted_pile_def(int bodies, InternalOrder order) {
  WorldDef def = default_world_def();
  def.bodies.count = bodies;
  def.bodies.internal_order = order;
  const double side = 30.0 * std::sqrt(bodies / 100.0);
  def.world.width = def.world.height = side;
  def.bodies.mean = {side / 2, side / 2};
  def.bodies.sigma = 4.65 * std::sqrt(bodies / 100.0);
  return def;
}

/// validate()'s message for p ("" when p is valid).
std::string validate_message(const LcpProblem& p) {
  try {
    p.validate();
  } catch (const InvalidArgument& e) {
    return e.what();
  }
  return "";
}

TEST(PgsColoredTrusted, TheEnginesProblemsSkipTheStructuralChecksCopiesDoNot) {
  for (const InternalOrder order : {InternalOrder::None, InternalOrder::Morton}) {
    World world(trusted_pile_def(300, order));
    PgsColoredProfile prof;
    PgsColoredDef d;
    d.profile = &prof;
    const auto solver = make_pgs_colored(d);
    SolverOptions o;
    o.max_sweeps = 10;
    o.record_theta = false;
    for (int k = 0; k < 30; ++k) world.step(*solver, o, World::WarmStart::PreviousLambda);
    ASSERT_GT(prof.solves, 0);
    EXPECT_EQ(prof.structure_trusted, prof.solves) << "every step's problem is the engine's own";

    // A copy is unstamped: checked whole, and the same solution.
    const long trusted = prof.structure_trusted;
    const LcpProblem copy = world.problem();
    ASSERT_GT(copy.rows(), 10);
    const SolveResult fine = solver->solve(copy, Eigen::VectorXd(), o);
    EXPECT_NE(fine.status, SolveStatus::InvalidInput);
    EXPECT_EQ(prof.structure_trusted, trusted) << "a copy is checked whole";

    // Structure broken after construction: rejected, with validate()'s message.
    LcpProblem broken = world.problem();
    int c = 0;
    while (!broken.constraints[c].has_friction()) ++c;
    broken.normal_row[static_cast<size_t>(broken.constraints[c].tangent_row)] = broken.rows() + 1;
    const std::string why = validate_message(broken);
    ASSERT_FALSE(why.empty());
    const SolveResult bad = solver->solve(broken, Eigen::VectorXd(), o);
    EXPECT_EQ(bad.status, SolveStatus::InvalidInput);
    EXPECT_NE(bad.message.find(why), std::string::npos) << bad.message << " | " << why;
    EXPECT_EQ(prof.structure_trusted, trusted);

    // The world goes on trusting the problems it builds.
    world.step(*solver, o, World::WarmStart::PreviousLambda);
    EXPECT_EQ(prof.structure_trusted, trusted + 1);
  }
}

}  // namespace
}  // namespace dc
