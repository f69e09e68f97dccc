// A solver variant tested on problem files with dc_lcp alone (no engine, no world): reads a
// Siconos LCP or 2D frictional-contact .dat, or an FCLIB file, with read_problem_file, solves it
// with a solver of your own (here projected Jacobi with under-relaxation, implementing
// dc::LcpSolver) and with the library's "newton-sparse", and prints the natural-map residual
// of each. Exit status 0 when the library's solver reaches its tolerance and the variant
// returns a finite λ inside the bounds.
//
//   solve_problem_file FILE [SWEEPS]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/problem_file.hpp"

namespace {

/// λ ← mid(lo, λ − ω D⁻¹ (A λ + b), hi) for all rows at once, ω = 0.5 [dimensionless].
class DampedJacobi final : public dc::LcpSolver {
 public:
  [[nodiscard]] std::string name() const override { return "damped-jacobi"; }
  [[nodiscard]] dc::SolveResult solve(const dc::LcpProblem& p, const Eigen::VectorXd& lambda0,
                                      const dc::SolverOptions& o) override {
    dc::SolveResult r;
    r.lambda = lambda0.size() == p.rows() ? lambda0 : Eigen::VectorXd::Zero(p.rows()).eval();
    const Eigen::VectorXd diag = p.A.diagonal();
    r.status = dc::SolveStatus::SweepLimit;
    for (r.sweeps = 0; r.sweeps < o.max_sweeps;) {
      ++r.sweeps;
      const Eigen::VectorXd w = p.A * r.lambda + p.b;
      Eigen::VectorXd next = r.lambda;
      for (int i = 0; i < p.rows(); ++i)
        if (diag[i] > 0) next[i] = r.lambda[i] - 0.5 * w[i] / diag[i];
      // Normal (fixed-bound) rows first, then the friction rows whose bounds they set.
      for (int pass = 0; pass < 2; ++pass)
        for (int i = 0; i < p.rows(); ++i)
          if (p.is_friction_row(i) == (pass == 1))
            next[i] = std::min(std::max(next[i], p.lower(i, next)), p.upper(i, next));
      const double theta = (next - r.lambda).lpNorm<Eigen::Infinity>();
      r.lambda = next;
      if (theta <= o.tolerance) {
        r.status = dc::SolveStatus::Converged;
        break;
      }
    }
    r.residual = dc::natural_residual(p, r.lambda);
    return r;
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: solve_problem_file FILE [SWEEPS]\n");
    return 2;
  }
  try {
    const dc::ProblemFile file = dc::read_problem_file(argv[1]);
    const dc::LcpProblem& p = file.lcp;
    dc::SolverOptions o;
    o.max_sweeps = argc > 2 ? std::atoi(argv[2]) : 2000;
    o.tolerance = 1e-10;
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.rows());
    const dc::SolveResult mine = DampedJacobi().solve(p, zero, o);
    const dc::SolveResult ref = dc::make_solver("newton-sparse")->solve(p, zero, dc::SolverOptions{});
    std::printf("%s: %s problem, %d rows\n", argv[1], dc::to_string(file.kind), p.rows());
    std::printf("  %-14s %-12s %6d sweeps  residual %.3g N\n", "damped-jacobi", dc::to_string(mine.status),
                mine.sweeps, mine.residual);
    std::printf("  %-14s %-12s %6d iters   residual %.3g N\n", "newton-sparse", dc::to_string(ref.status),
                ref.sweeps, ref.residual);
    bool inside = mine.lambda.allFinite();
    for (int i = 0; i < p.rows() && inside; ++i)
      inside = mine.lambda[i] >= p.lower(i, mine.lambda) - 1e-12 && mine.lambda[i] <= p.upper(i, mine.lambda) + 1e-12;
    return ref.status == dc::SolveStatus::Converged && inside ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "solve_problem_file: %s\n", e.what());
    return 1;
  }
}
