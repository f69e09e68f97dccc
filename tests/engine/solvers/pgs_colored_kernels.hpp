#pragma once
// Shared by the pgs-colored engine tests: the kernels this CPU runs (scalar always, AVX2 and
// AVX-512 where present; the portable build runs the same list: the AVX kernels are chosen at
// run time), one PgsColoredDef each, for the tests that compare the kernels with each other or
// with pgs; the bit-equality those comparisons assert; a box pyramid's and any settled world's
// contact problem, and a warm start with both signs.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "engine/fixed_sweeps.hpp"
#include "bytes_equal.hpp"

namespace dc::test {

inline std::vector<PgsColoredDef> pgs_colored_kernel_defs() {
  std::vector<PgsColoredDef> out;
  for (PgsColoredKernel k : {PgsColoredKernel::Scalar, PgsColoredKernel::Avx2, PgsColoredKernel::Avx512}) {
    if (!pgs_colored_kernel_available(k)) continue;
    PgsColoredDef d;
    d.kernel = k;
    out.push_back(d);
  }
  return out;
}

/// The same λ (bit for bit, row by row), θ and sweep count.
inline void expect_bit_equal(const SolveResult& a, const SolveResult& b, const std::string& what) {
  ASSERT_EQ(a.lambda.size(), b.lambda.size()) << what;
  for (Eigen::Index i = 0; i < a.lambda.size(); ++i) ASSERT_EQ(a.lambda[i], b.lambda[i]) << what << " row " << i;
  ASSERT_EQ(a.theta, b.theta) << what;
  EXPECT_EQ(a.sweeps, b.sweeps) << what;
}

/// Bit-equal λ, θ, sweeps, status and residual (memcmp: the same bits, ±0 and NaN included).
inline void expect_same_bits(const SolveResult& a, const SolveResult& b, const std::string& what) {
  ASSERT_EQ(a.lambda.size(), b.lambda.size()) << what;
  EXPECT_TRUE(test::bytes_equal(a.lambda, b.lambda)) << what;
  EXPECT_EQ(a.theta, b.theta) << what;
  EXPECT_EQ(a.sweeps, b.sweeps) << what;
  EXPECT_EQ(a.status, b.status) << what;
  EXPECT_EQ(0, std::memcmp(&a.residual, &b.residual, sizeof(double))) << what << ": " << a.residual << " vs " << b.residual;
}

/// A box pyramid (base `base`, two-point manifolds on every face, friction μ) after `steps`
/// steps of pgs at 100 sweeps, warm-started from the previous λ.
inline LcpProblem pyramid_problem(int base, int steps, double mu = 0.5) {
  WorldDef def = stress::box_pyramid(base);
  def.contact.friction = mu;
  World world(def);
  const auto pgs = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 100;
  o.record_theta = false;
  for (int k = 0; k < steps; ++k) world.step(*pgs, o, World::WarmStart::PreviousLambda);
  world.collide();
  return world.assemble();
}

/// The problem of `def`'s world after `steps` steps of pgs (exactly 100 sweeps, previous λ as start).
inline LcpProblem settled_problem(const WorldDef& def, int steps) {
  World world(def);
  const auto pgs = make_solver("pgs");
  SolverOptions o = fixed_sweeps(100);
  o.record_theta = false;
  for (int k = 0; k < steps; ++k) world.step(*pgs, o, World::WarmStart::PreviousLambda);
  world.collide();
  return world.assemble();
}

/// A warm start with both signs on friction rows and zeros on some normals.
inline Eigen::VectorXd mixed_sign_start(const LcpProblem& p) {
  Eigen::VectorXd l0(p.rows());
  for (int i = 0; i < p.rows(); ++i) l0[i] = p.is_friction_row(i) ? 0.1 * (i % 3 - 1) : 0.5 * (i % 4);
  return l0;
}

}  // namespace dc::test
