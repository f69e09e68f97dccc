#pragma once
// Private factories of the solver family; make_solver (solver_registry.cpp) maps names to them.
#include <memory>

#include "dc/lcp/lcp_solver.hpp"

namespace dc::solvers {
std::unique_ptr<LcpSolver> make_pgs_matrix_free();  // "pgs"            pgs_matrix_free_solver.cpp
std::unique_ptr<LcpSolver> make_pgs_colored();      // "pgs-colored"    pgs_colored.cpp
std::unique_ptr<LcpSolver> make_pgs_assembled();    // "pgs-assembled"  pgs_assembled.cpp
std::unique_ptr<LcpSolver> make_psor();             // "psor"           psor.cpp
std::unique_ptr<LcpSolver> make_jacobi();           // "jacobi"         jacobi.cpp
std::unique_ptr<LcpSolver> make_lemke();            // "lemke"          lemke.cpp
std::unique_ptr<LcpSolver> make_newton();           // "newton"         newton.cpp
std::unique_ptr<LcpSolver> make_nncg();             // "nncg"           nncg.cpp

/// The newton solver as a function. With `seek_certificate`, a standard LCP (lo = 0,
/// hi = ∞, no friction; n ≤ kFarkasMaxN) that newton fails on is checked for a Farkas
/// certificate of infeasibility (lcp_proofs.hpp): found → Infeasible. Without it (lemke's
/// polish and fallback starts, which search for the certificate themselves) never Infeasible.
SolveResult newton_solve(const LcpProblem& p, const Eigen::VectorXd& lambda0, const SolverOptions& o,
                         bool seek_certificate);

struct SweepWatch;  // solver_common.hpp

/// The nncg solver as a function, with the caller's look at its iterate every watch->every
/// sweeps (null: none; the same run as make_nncg()'s solve). One run keeps nncg's momentum and
/// Δu across the looks (prox-newton's lead stage judges it this way).
SolveResult nncg_solve(const LcpProblem& p, const Eigen::VectorXd& lambda0, const SolverOptions& o,
                       const SweepWatch* watch);

/// The nncg-colored solver `solver` (from make_nncg_colored, pgs_colored.hpp; another solver:
/// InvalidArgument) as a function, with the caller's look at its iterate (in row order) every
/// watch->every sweeps, as nncg_solve's: one run keeps the momentum and Δu across the looks. The
/// solver object keeps its colouring and buffers from solve to solve (prox-newton's lead stage
/// keeps one).
SolveResult nncg_colored_solve(LcpSolver& solver, const LcpProblem& p, const Eigen::VectorXd& lambda0,
                               const SolverOptions& o, const SweepWatch* watch);

/// The assembled PGS/PSOR iteration as a function (also used by pgs without J and by the
/// PGS polish of newton).
SolveResult solve_assembled_gauss_seidel(const LcpProblem& p, const Eigen::VectorXd& lambda0,
                                         const SolverOptions& o, double omega, const std::string& name);
}  // namespace dc::solvers
