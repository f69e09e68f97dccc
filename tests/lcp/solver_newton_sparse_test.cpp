// newton-sparse against lemke and newton, its factorisation paths against each other, warm
// starts, and the problems that break Newton methods (rank deficiency, μ = 0, mass ratios
// 1e6, duplicated contacts, NaN guesses): an honest status, a finite λ, a bounded run.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdlib>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/newton_sparse/gmres.hpp"

namespace dc {
namespace {

// dot_in_lanes (GMRES's products with NewtonSparseDef::lane_dot) sums in interleaved lanes and a tail:
// on values whose every partial sum is exact in double it equals the exact sum for every length,
// whatever lane or the tail an element falls in, and a product with a single nonzero entry
// finds that entry at every index.
TEST(NewtonSparseDot, LaneDotIsExactOnExactlyRepresentableSums) {
  for (int n = 0; n <= 41; ++n) {
    Eigen::VectorXd a(n), b(n);
    long long exact = 0;
    for (int i = 0; i < n; ++i) {
      a[i] = static_cast<double>((i * 7) % 13 - 6);
      b[i] = static_cast<double>((i * 5) % 11 - 5);
      exact += static_cast<long long>(a[i]) * static_cast<long long>(b[i]);
    }
    EXPECT_EQ(solvers::dot_in_lanes(a, b), static_cast<double>(exact)) << "n = " << n;
    for (int k = 0; k < n; ++k) {
      Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
      e[k] = 0.5;
      EXPECT_EQ(solvers::dot_in_lanes(e, b), 0.5 * b[k]) << "n = " << n << ", k = " << k;
    }
  }
}

SolverOptions options(int iterations = 200) {
  SolverOptions o;
  o.max_sweeps = iterations;
  return o;
}

double bound(const LcpProblem& p) {
  double s = 1.0;
  for (int i = 0; i < p.rows(); ++i) s = std::max(s, std::abs(p.b[i]));
  return 1e-9 * s;
}

SolveResult newton_sparse(const LcpProblem& p, const Eigen::VectorXd& lambda0 = {}, const NewtonSparseDef& def = {}) {
  return NewtonSparseSolver(def).solve(p, lambda0, options());
}

/// Honest: Converged exactly when the returned λ meets the target; λ finite; bounded run.
void expect_honest(const SolveResult& r, const LcpProblem& p, const std::string& what) {
  EXPECT_EQ(r.lambda.size(), p.rows()) << what;
  EXPECT_TRUE(r.lambda.allFinite()) << what;
  EXPECT_LE(r.sweeps, 200) << what;
  EXPECT_EQ(r.status == SolveStatus::Converged, natural_residual(p, r.lambda) <= bound(p))
      << what << ": " << to_string(r.status) << " " << r.message;
}

/// The same contact problem with some bodies 1e6 times heavier than others.
LcpProblem mass_ratio_problem(uint64_t seed) {
  test::TestRng rng(seed);
  LcpProblem p = test::random_contact(20, 30, true, rng);
  for (int k = 0; k < p.inv_mass.size() / 3; k += 2) p.inv_mass.segment(3 * k, 3) *= 1e-6;
  const SparseRowMatrix Minv_Jt_dt = (p.inv_mass.asDiagonal() * SparseRowMatrix(p.J.transpose())) * p.dt;
  p.A = p.J * Minv_Jt_dt;
  p.A.makeCompressed();
  return p;
}

// NewtonSparseDef::lane_dot changes GMRES's rounding only: on frictional contact problems (GMRES
// on the sliding rows' coupling) and a deep pile it converges where the index-order products
// do, honestly, with the same contact velocities w = Aλ + b to the target's order, and reruns
// are bit-equal.
TEST(NewtonSparse, LaneDotReachesTheSameVelocitiesAsIndexOrderDot) {
  std::vector<LcpProblem> problems;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    test::TestRng rng(seed + 700);
    problems.push_back(test::random_contact(30, 40, true, rng));
  }
  problems.push_back(test::deep_pile(4, 6, 0.5));
  NewtonSparseDef lanes;
  lanes.lane_dot = true;
  for (std::size_t k = 0; k < problems.size(); ++k) {
    const LcpProblem& p = problems[k];
    const SolveResult a = newton_sparse(p);
    const SolveResult b = newton_sparse(p, {}, lanes);
    const SolveResult again = newton_sparse(p, {}, lanes);
    expect_honest(b, p, "lane_dot problem " + std::to_string(k));
    EXPECT_EQ(a.status == SolveStatus::Converged, b.status == SolveStatus::Converged) << "problem " << k;
    EXPECT_TRUE(b.lambda == again.lambda) << "problem " << k;
    if (a.status == SolveStatus::Converged && b.status == SolveStatus::Converged) {
      const double tol = 1e3 * bound(p);
      EXPECT_LE((lcp_velocity(p, a.lambda) - lcp_velocity(p, b.lambda)).cwiseAbs().maxCoeff(), tol) << "problem " << k;
    }
  }
}

TEST(NewtonSparse, SameSolutionAsLemkeOnProblemsWithAUniqueSolution) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    test::TestRng rng(seed + 100);
    const LcpProblem spd = test::random_spd(40, rng);  // positive definite: unique solution
    test::TestRng rng2(seed + 300);
    const LcpProblem contact = test::random_contact(30, 25, false, rng2);  // fewer rows than dofs
    for (const LcpProblem* p : {&spd, &contact}) {
      const SolveResult a = make_solver("lemke")->solve(*p, {}, options(3000));
      SolverOptions tight = options();
      tight.exact_tolerance = 1e-13;  // λ's error is the residual times ‖A⁻¹‖: aim well below 1e-7
      const SolveResult b = NewtonSparseSolver().solve(*p, {}, tight);
      ASSERT_EQ(a.status, SolveStatus::Converged) << a.message;
      ASSERT_EQ(b.status, SolveStatus::Converged) << b.message;
      EXPECT_LE((a.lambda - b.lambda).cwiseAbs().maxCoeff(), 1e-7) << "seed " << seed;
    }
  }
}

TEST(NewtonSparse, SameContactVelocitiesAsLemkeOnRankDeficientProblems) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed);
    const LcpProblem c = test::random_contact(10, 60, false, rng);  // 60 rows, rank ≤ 30
    const SolveResult a = make_solver("lemke")->solve(c, {}, options(3000)), b = newton_sparse(c);
    ASSERT_EQ(b.status, SolveStatus::Converged) << b.message;
    // λ is not unique, w = A λ + b is (convex QP).
    EXPECT_LE((lcp_velocity(c, a.lambda) - lcp_velocity(c, b.lambda)).cwiseAbs().maxCoeff(), 1e-6);
  }
}

TEST(NewtonSparse, AgreesWithNewtonOnFrictionProblems) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    test::TestRng rng(seed + 400);
    const LcpProblem p = test::random_contact(30, 25, true, rng);  // 50 rows ≤ 90 dofs
    const SolveResult a = make_solver("newton")->solve(p, {}, options(3000)), b = newton_sparse(p);
    ASSERT_EQ(a.status, SolveStatus::Converged) << a.message;
    ASSERT_EQ(b.status, SolveStatus::Converged) << b.message;
    EXPECT_LE((lcp_velocity(p, a.lambda) - lcp_velocity(p, b.lambda)).cwiseAbs().maxCoeff(), 1e-6) << seed;
    for (int i = 0; i < p.rows(); ++i) {  // inside the friction box
      if (!p.is_friction_row(i)) continue;
      const double ln = b.lambda[p.normal_row[static_cast<size_t>(i)]];
      EXPECT_LE(std::abs(b.lambda[i]), p.mu[i] * ln + 1e-9 * std::max(1.0, ln));
    }
  }
}

TEST(NewtonSparse, SparseFileAndFactorisationPathsAgree) {
  // With J (assembled matrix formed for the solve), from A alone (a file), with the
  // SimplicialLDLT fallback instead of CHOLMOD, without analysis reuse, with the coupled
  // system factorised by LU instead of GMRES, with CHOLMOD's supernodal choice: one solution.
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 500);
    LcpProblem with_j = test::random_contact(60, 120, true, rng);
    const LcpProblem file = test::without_jacobian(with_j);
    with_j.A = SparseRowMatrix();  // the solver forms A from J
    NewtonSparseDef ldlt;
    ldlt.cholmod = false;
    NewtonSparseDef fresh;
    fresh.reuse_analysis = false;
    NewtonSparseDef lu;
    lu.coupled_lu = true;
    NewtonSparseDef supernodal;
    supernodal.supernodal = true;
    const SolveResult a = newton_sparse(file), b = newton_sparse(with_j), c = newton_sparse(file, {}, ldlt),
                      d = newton_sparse(file, {}, fresh), e = newton_sparse(file, {}, lu),
                      f = newton_sparse(file, {}, supernodal);
    for (const SolveResult* r : {&a, &b, &c, &d, &e, &f}) {
      ASSERT_EQ(r->status, SolveStatus::Converged) << r->message;
      EXPECT_LE((lcp_velocity(file, r->lambda) - lcp_velocity(file, a.lambda)).cwiseAbs().maxCoeff(), 1e-6);
    }
  }
}

/// Sets DC_CHOLMOD for the lifetime of the object, then unsets it.
struct CholmodSwitch {
  explicit CholmodSwitch(const char* mode) { ::setenv("DC_CHOLMOD", mode, 1); }
  ~CholmodSwitch() { ::unsetenv("DC_CHOLMOD"); }
  CholmodSwitch(const CholmodSwitch&) = delete;
  CholmodSwitch& operator=(const CholmodSwitch&) = delete;
};

TEST(NewtonSparse, TheCholmodSwitchChangesTheFactorisationNotTheSolution) {
  // DC_CHOLMOD=simplicial|supernodal overrides the solvers' own choice (docs/solvers.md): both
  // give the same contact velocities, as prox-newton (body space) does; any other value is a
  // ConfigError.
  test::TestRng rng(611);
  const LcpProblem p = test::random_contact(60, 120, true, rng);
  const SolveResult plain = newton_sparse(p);
  ASSERT_EQ(plain.status, SolveStatus::Converged) << plain.message;
  for (const char* mode : {"simplicial", "supernodal"}) {
    const CholmodSwitch on(mode);
    for (const char* name : {"newton-sparse", "prox-newton"}) {
      const SolveResult r = make_solver(name)->solve(p, {}, options(3000));
      ASSERT_EQ(r.status, SolveStatus::Converged) << mode << " " << name << ": " << r.message;
      EXPECT_LE((lcp_velocity(p, r.lambda) - lcp_velocity(p, plain.lambda)).cwiseAbs().maxCoeff(), 1e-6) << mode << " " << name;
    }
  }
  const CholmodSwitch bad("fastest");
  EXPECT_THROW((void)newton_sparse(p), ConfigError);
}

TEST(NewtonSparse, DenseAndSparseStorageGiveTheSameIterates) {
  test::TestRng rng(7);
  const LcpProblem spd = test::random_spd(30, rng);
  const LcpProblem dense = LcpProblem::standard(Eigen::MatrixXd(spd.A), Eigen::VectorXd(spd.b));
  const SolveResult a = newton_sparse(spd), b = newton_sparse(dense);
  ASSERT_EQ(a.status, SolveStatus::Converged);
  EXPECT_EQ(a.sweeps, b.sweeps);
  EXPECT_LE((a.lambda - b.lambda).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(NewtonSparse, FromTheSolutionConvergesInAtMostOneIteration) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 600);
    const LcpProblem p = test::random_contact(50, 100, true, rng);
    const SolveResult star = newton_sparse(p);
    ASSERT_EQ(star.status, SolveStatus::Converged) << star.message;
    const SolveResult again = newton_sparse(p, star.lambda);
    EXPECT_EQ(again.status, SolveStatus::Converged);
    EXPECT_LE(again.sweeps, 1);
  }
}

TEST(NewtonSparse, ConvergesFastNearASolutionWithSlidingContacts) {
  // Semismooth Newton with the friction coupling in its Jacobian converges superlinearly:
  // from a perturbed solution with sliding contacts (|λ_t| = μ λ_n > 0) a few iterations
  // suffice. Dropping the coupling leaves a linearly converging fixed-point iteration.
  int sliding_problems = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 700);
    const LcpProblem p = test::random_contact(30, 25, true, rng, 0.2);
    SolverOptions tight = options();
    tight.exact_tolerance = 1e-13;
    NewtonSparseSolver solver;
    const SolveResult star = solver.solve(p, {}, tight);
    ASSERT_EQ(star.status, SolveStatus::Converged) << star.message;
    int sliding = 0;
    for (int i = 0; i < p.rows(); ++i) {
      if (!p.is_friction_row(i)) continue;
      const double ln = star.lambda[p.normal_row[static_cast<size_t>(i)]];
      sliding += ln > 1e-6 && std::abs(std::abs(star.lambda[i]) - p.mu[i] * ln) < 1e-12 * std::max(1.0, ln);
    }
    if (sliding == 0) continue;
    ++sliding_problems;
    Eigen::VectorXd start = star.lambda;
    for (int i = 0; i < start.size(); ++i) start[i] *= 1.0 + 1e-3 * rng.uniform(-1, 1);
    const SolveResult r = solver.solve(p, start, tight);
    EXPECT_EQ(r.status, SolveStatus::Converged) << r.message;
    EXPECT_LE(r.sweeps, 6) << "seed " << seed << ", " << sliding << " sliding contacts";
  }
  EXPECT_GE(sliding_problems, 3);
}

TEST(NewtonSparse, InexactKrylovStepsReachTheSameTargetWithFewerKrylovIterations) {
  // krylov_forcing stops GMRES at η_k = min(forcing, ‖H_k‖/‖H_0‖) instead of 1e-12: the
  // directions are inexact far from the solution and exact in the limit, so the solve still
  // ends at the unregularised target, with fewer GMRES iterations in all.
  NewtonSparseDef exact;
  exact.krylov_forcing = 0.0;
  const NewtonSparseDef inexact;  // the default forcing
  ASSERT_GT(inexact.krylov_forcing, 0.0);
  long krylov_exact = 0, krylov_inexact = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 900);
    const LcpProblem p = test::random_contact(30, 25, true, rng, 0.2);
    NewtonSparseSolver a(exact), b(inexact);
    const SolveResult ra = a.solve(p, {}, options());
    const SolveResult rb = b.solve(p, {}, options());
    EXPECT_EQ(ra.status, SolveStatus::Converged) << "seed " << seed << ": " << ra.message;
    EXPECT_EQ(rb.status, SolveStatus::Converged) << "seed " << seed << ": " << rb.message;
    EXPECT_LE(natural_residual(p, rb.lambda), bound(p)) << "seed " << seed;
    krylov_exact += a.last_stats().krylov_iterations;
    krylov_inexact += b.last_stats().krylov_iterations;
  }
  EXPECT_GT(krylov_exact, 0);  // the problems have sliding friction coupled
  EXPECT_LT(krylov_inexact, krylov_exact);
}

TEST(NewtonSparse, ReusesTheAnalysisWhileThePatternHolds) {
  test::TestRng rng(800);
  const LcpProblem p = test::random_contact(50, 100, true, rng);
  NewtonSparseSolver solver;
  const SolveResult a = solver.solve(p, {}, options());
  const NewtonSparseStats first = solver.last_stats();
  const SolveResult b = solver.solve(p, {}, options());
  const NewtonSparseStats second = solver.last_stats();
  EXPECT_EQ(first.analyses, 1);
  EXPECT_EQ(second.analyses, 0);
  EXPECT_GE(second.factorizations, 1);
  EXPECT_EQ(a.lambda, b.lambda);  // reuse changes no result: bit-equal reruns
  EXPECT_EQ(a.sweeps, b.sweeps);
}

TEST(NewtonSparse, HardProblemsGetAnHonestStatus) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 900);
    const LcpProblem deficient = test::random_contact(10, 80, true, rng);  // 160 rows, 30 dofs
    const LcpProblem frictionless = test::random_contact(10, 60, false, rng);
    const LcpProblem mixed = test::random_contact(20, 40, true, rng, 0.5, 3);  // every 3rd μ = 0
    const LcpProblem heavy = mass_ratio_problem(seed);
    // Degenerate contacts: every contact twice (identical rows; A has repeated rows).
    test::TestRng rng2(seed + 950);
    LcpProblem twice = test::random_contact(15, 20, true, rng2);
    {
      const int n = twice.rows();
      LcpProblem d;
      SparseRowMatrix J2(2 * n, twice.J.cols());
      std::vector<Eigen::Triplet<double>> trip;
      for (int k = 0; k < twice.J.outerSize(); ++k)
        for (SparseRowMatrix::InnerIterator it(twice.J, k); it; ++it) {
          trip.emplace_back(it.row(), it.col(), it.value());
          trip.emplace_back(it.row() + n, it.col(), it.value());
        }
      J2.setFromTriplets(trip.begin(), trip.end());
      d.J = J2;
      d.inv_mass = twice.inv_mass;
      d.dt = twice.dt;
      d.b.resize(2 * n);
      d.b << twice.b, twice.b;
      d.lo.resize(2 * n);
      d.lo << twice.lo, twice.lo;
      d.hi.resize(2 * n);
      d.hi << twice.hi, twice.hi;
      d.mu.resize(2 * n);
      d.mu << twice.mu, twice.mu;
      d.normal_row.resize(static_cast<size_t>(2 * n));
      for (int i = 0; i < n; ++i) {
        const int nr = twice.normal_row[static_cast<size_t>(i)];
        d.normal_row[static_cast<size_t>(i)] = nr;
        d.normal_row[static_cast<size_t>(i + n)] = nr < 0 ? -1 : nr + n;
      }
      d.ensure_assembled_matrix();
      twice = d;
    }
    for (const auto& [p, what] : {std::pair{&deficient, "rank-deficient"}, {&frictionless, "mu = 0"},
                                  {&mixed, "mixed mu"}, {&heavy, "mass ratio 1e6"}, {&twice, "duplicated"}}) {
      const SolveResult r = newton_sparse(*p);
      expect_honest(r, *p, what);
      EXPECT_EQ(r.status, SolveStatus::Converged) << what << " seed " << seed << ": " << r.message;
    }
  }
}

TEST(NewtonSparse, NaNOrWrongSizedGuessIsInvalidInputWithAFiniteLambda) {
  test::TestRng rng(1000);
  const LcpProblem p = test::random_contact(10, 15, true, rng);
  Eigen::VectorXd bad = Eigen::VectorXd::Zero(p.rows());
  bad[3] = std::nan("");
  for (const Eigen::VectorXd& guess : {bad, Eigen::VectorXd(Eigen::VectorXd::Zero(p.rows() + 1))}) {
    const SolveResult r = newton_sparse(p, guess);
    EXPECT_EQ(r.status, SolveStatus::InvalidInput);
    EXPECT_TRUE(r.lambda.allFinite());
    EXPECT_FALSE(r.message.empty());
  }
  // A huge finite guess overflows A λ: the solver restarts from zero and says so.
  const SolveResult h = newton_sparse(p, Eigen::VectorXd::Constant(p.rows(), 1e308));
  expect_honest(h, p, "huge guess");
  EXPECT_EQ(h.status, SolveStatus::Converged) << h.message;
}

TEST(NewtonSparse, AnyGuessConverges) {
  // Globalisation: random, negative and far-too-large guesses all reach the tolerance.
  test::TestRng rng(1100);
  const LcpProblem p = test::random_contact(40, 90, true, rng);
  for (int k = 0; k < 5; ++k) {
    Eigen::VectorXd guess(p.rows());
    for (int i = 0; i < guess.size(); ++i) guess[i] = rng.uniform(-100, 100) * (k + 1);
    const SolveResult r = newton_sparse(p, guess);
    expect_honest(r, p, "random guess");
    EXPECT_EQ(r.status, SolveStatus::Converged) << r.message;
  }
}

}  // namespace
}  // namespace dc
