#pragma once
// Private factories of the solver family; make_solver (solver_registry.cpp) maps names to them.
#include <memory>

#include "dc/engine/lcp_solver.hpp"

namespace dc::solvers {
std::unique_ptr<LcpSolver> make_pgs_matrix_free();  // "pgs"            pgs_matrix_free.cpp
std::unique_ptr<LcpSolver> make_pgs_assembled();    // "pgs-assembled"  pgs_assembled.cpp
std::unique_ptr<LcpSolver> make_psor();             // "psor"           psor.cpp
std::unique_ptr<LcpSolver> make_jacobi();           // "jacobi"         jacobi.cpp
std::unique_ptr<LcpSolver> make_lemke();            // "lemke"          lemke.cpp
std::unique_ptr<LcpSolver> make_newton();           // "newton"         newton.cpp

/// The assembled PGS/PSOR iteration as a function (also used by pgs without J and by the
/// PGS polish of newton).
SolveResult solve_assembled_gauss_seidel(const LcpProblem& p, const Eigen::VectorXd& lambda0,
                                         const SolverOptions& o, double omega, const std::string& name);
}  // namespace dc::solvers
