#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): the input checks of a solve
// (LcpProblem::validate and the initial guess, solver_common.hpp's check_input) with their
// per-row and per-contact scans on threads, because serial they are a noticeable part of every
// solve on large piles; λ⁰ is used in place, never copied.
#include <optional>
#include <string>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"

namespace dc::colored {

/// check_input(p, lambda0, solver) of solver_common.hpp, the same verdict and message: the scans
/// of b, the bounds, μ, A, λ⁰ and the contacts run on `threads` threads and only say whether
/// everything passed (an order-free AND); on a failure the serial check runs and names the first
/// bad entry with check_input's message. On success returns nullopt and sets `start` to the
/// entries of lambda0, or of `zeros` (resized to the rows and zeroed) when lambda0 is empty — no
/// copy of λ⁰. That no row is owned
/// by two contacts follows from their rows increasing in contact order (as the engine numbers
/// them); otherwise each row's owner is recorded and read back. With contacts, a friction row's
/// coupling is checked through its contact when the contacts claim every row once (counted).
/// `owner` is that pass's scratch (resized to the rows, never cleared: each row is read back
/// only by the contacts claiming it),
/// kept by the caller so that a solve allocates nothing for the checks in steady state.
/// A problem whose StructureStamp holds (built valid by construction, assemble_lcp) has only
/// what can still fail checked: b, λ⁰ and A finite; `trusted` says so (true only when those
/// passed; any failure runs the full serial checks for the message).
std::optional<SolveResult> check_input(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda0, const std::string& solver,
                                       int threads, Eigen::VectorXd& zeros, const double*& start,
                                       std::vector<int>& owner, bool& trusted);

}  // namespace dc::colored
