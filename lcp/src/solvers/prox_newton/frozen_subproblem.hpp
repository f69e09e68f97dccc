#pragma once
// The convex subproblem of one prox-newton pass (dc/lcp/prox_newton.hpp): friction bounds
// frozen at s = μ max(0, λ_n^k) and the proximal term ½ δ ‖λ − λ^k‖², i.e. the box QP
//     min_λ ½ λᵀ(A + δI)λ + cᵀλ,   c = b − δ λ^k,   lo ≤ λ ≤ hi (all bounds fixed),
// and the row modes of the hard problem the outer loop compares between passes.
#include <Eigen/Core>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"

namespace dc::solvers::prox {

struct FrozenSubproblem {
  Eigen::VectorXd lo, hi;  ///< fixed bounds of every row [N] (friction rows: ∓s)
  Eigen::VectorXd centre;  ///< λ^k [N]
  Eigen::VectorXd c;       ///< b − δ λ^k [m/s]
  double delta = 0;        ///< δ [m/(N·s)]
  double tolerance = 0;    ///< stop when the subproblem's natural residual is ≤ this [N]
  int max_iterations = 0;  ///< Newton iterations at most
  /// Body space only: friction bounds follow the iterate (s_i = μ_i max(0, λ_n) of the same λ)
  /// instead of lo/hi: the hard proximal subproblem. lo/hi still bound the other rows.
  bool coupled = false;
  /// Body space only: H's direction by CG preconditioned with the kept factor of an earlier H,
  /// refactorising only when CG needs more than this many iterations (0: refactorise whenever D
  /// or δ changed).
  int stale_factor_iterations = 0;
};

/// Work of one subproblem solve.
struct SubproblemOutcome {
  int iterations = 0;         ///< Newton iterations
  int line_search_steps = 0;  ///< merit trials or 1D Newton steps
  int factorizations = 0, analyses = 0;
  int full_steps = 0;         ///< body space, coupled: Newton steps accepted whole (t = 1)
  int krylov_iterations = 0;  ///< body space, coupled: GMRES iterations for the coupled direction
  int cg_iterations = 0;      ///< body space: CG iterations with a kept (stale) factor
  bool converged = false;     ///< subproblem residual ≤ tolerance
  bool failed = false;        ///< no usable direction (factorisation failed, non-finite values)
};

/// The subproblem at centre λ^k with weight δ: bounds frozen at λ^k (s = μ max(0, λ_n^k)).
void freeze(const LcpProblem& p, const Eigen::VectorXd& centre, double delta, FrozenSubproblem& sub);

/// Natural residual of the subproblem at λ given w̃ = (A + δI)λ + c:
/// max_i |λ_i − clamp(λ_i − w̃_i, lo_i, hi_i)| [N].
double subproblem_residual(const FrozenSubproblem& sub, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w);

/// Mode of every row of the hard problem at λ: 0 at its lower bound, 1 free, 2 at its upper
/// bound (y = λ − w against the effective bounds, as newton-sparse's linearisation reads them).
std::vector<char> hard_modes(const LcpProblem& p, const Eigen::VectorXd& lambda);

}  // namespace dc::solvers::prox
