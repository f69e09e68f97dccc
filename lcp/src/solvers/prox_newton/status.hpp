#pragma once
// The one place prox-newton decides whether an iterate is a solution: the natural-map residual
// of the HARD problem (Coulomb bounds moving with λ_n, no proximal term, no regularisation)
// against the target every exact solver uses. Every stop test goes through these functions;
// the final status is then decided by the shared rule (solver_common.hpp, decide_status), and
// its message names the part that produced the returned iterate (Finisher).
#include <Eigen/Core>
#include <string>

#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "solvers/solver_common.hpp"

namespace dc::solvers::prox {

/// target [N]: options.tolerance when > 0, else the shared solution target (solution_target).
inline double status_target(const LcpProblem& p, const SolverOptions& o) {
  return o.tolerance > 0 ? o.tolerance : solution_target(p, o);
}

/// max_i |λ_i − mid(lo_i(λ), λ_i − w_i, hi_i(λ))| of the hard problem [N].
inline double hard_residual(const LcpProblem& p, const Eigen::VectorXd& lambda) { return natural_residual(p, lambda); }

/// True when a hard residual meets the target.
inline bool reached(double residual, double target) { return residual <= target; }

/// The status of a finished solve: Converged when reached; else SweepLimit when the iteration
/// budget ran out, Failed when the method stopped for another reason.
inline SolveStatus final_status(double residual, double target, bool budget_exhausted) {
  if (reached(residual, target)) return SolveStatus::Converged;
  return budget_exhausted ? SolveStatus::SweepLimit : SolveStatus::Failed;
}

/// Which part produced the returned iterate.
enum class Finisher { Guess, Lead, Prox, NewtonSparse, ProximalPoint, Pivot, Nncg, Continuation };

/// The part's name in the status message ("… by the nncg safeguard").
inline const char* to_string(Finisher f) {
  switch (f) {
    case Finisher::Guess: return "the guess";
    case Finisher::Lead: return "nncg lead stage";
    case Finisher::Prox: return "prox";
    case Finisher::NewtonSparse: return "newton-sparse finish";
    case Finisher::ProximalPoint: return "proximal newton-sparse finish";
    case Finisher::Pivot: return "lemke pivoting finish";
    case Finisher::Nncg: return "nncg safeguard";
    case Finisher::Continuation: return "mu continuation finish";
  }
  return "?";
}

/// SolveResult::message of a finished solve: the part that produced the returned iterate and
/// the work of every part ("finished by prox: 3 passes, 9 Newton + 0 finish iterations, …").
inline std::string work_message(Finisher by, const ProxNewtonStats& st) {
  const auto n = [](int k) { return std::to_string(k); };
  std::string m = std::string("finished by ") + to_string(by) + ": ";
  if (st.lead_sweeps > 0) m += n(st.lead_sweeps) + " lead sweeps, ";
  m += n(st.outer) + " passes, " + n(st.newton) + " Newton + " + n(st.finish_newton) + " finish iterations, " +
       n(st.factorizations) + " factorisations, " + n(st.safeguard_sweeps) + " nncg sweeps";
  if (st.pivots > 0) m += ", " + n(st.pivots) + " lemke pivots";
  if (st.continuation_solves > 0) m += ", " + n(st.continuation_solves) + " continuation solves";
  return m;
}

}  // namespace dc::solvers::prox
