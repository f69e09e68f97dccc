#pragma once
// "newton-sparse": warm-started semismooth Newton for the engine's exact box-friction LCP
// (docs/solvers.md "newton-sparse"), sparse factorisations by SuiteSparse CHOLMOD. It drives
//     H(λ)_i = λ_i − mid(lo_i(λ), λ_i − w_i, hi_i(λ)),   w = A λ + b,   lo/hi = ∓μ max(0, λ_n)
// to zero, the friction bounds moving with λ_n inside every step. Each iteration solves, on
// the free rows F (clamped rows C move by Δ_C = d_C + S Δ_F),
//     (A_FF + ρI + A_FC S) Δ_F = −w_F − A_FC d_C,   ρ = regularization·max_i A_ii,
// A_FF + ρI by CHOLMOD (analysis kept while A's pattern holds), the coupling by preconditioned
// GMRES; a line search on ½‖H‖² (PGS sweeps when it fails) globalises. It stops on the
// UNREGULARISED natural map at target = options.tolerance [N] when > 0, else solution_target.
// Status: Converged only when the returned λ passes the solution test (solution_target); a stop
// at a looser options.tolerance is ToleranceReached; SweepLimit after max_sweeps iterations; Failed after `max_stalls` iterations without decrease;
// InvalidInput for an invalid problem or guess. λ is always finite: the best iterate.
#include <functional>
#include <memory>

#include "dc/lcp/lcp_solver.hpp"

namespace dc {

struct NewtonSparseDef {
  /// ρ / max_i A_ii: proximal regularisation of the free block (dimensionless, default 1e-10).
  /// Only the step uses it; convergence is judged on the unregularised natural map.
  double regularization = 1e-10;
  /// PGS sweeps (assembled, coupled friction bounds) before each Newton direction (default 0).
  int smoothing_sweeps = 0;
  /// PGS sweeps taken instead of a step when the line search fails (default 5), doubled after
  /// each further consecutive failure, at most 2^fallback_doublings-fold (default 8; PGS carries
  /// a degenerate iterate onwards).
  int fallback_sweeps = 5;
  int fallback_doublings = 8;
  /// The fallback sweeps with NNCG's Fletcher–Reeves momentum (nncg's method on the assembled
  /// A, a fresh direction per batch; default false: plain PGS). Where the line search fails on
  /// a degenerate iterate (far more rows than body dofs), PGS's slow linear rate is what the
  /// batches pay for; the momentum lowers ‖H‖ in fewer sweeps of the same cost.
  bool fallback_momentum = false;
  /// Stop (as stalled, Failed) after a fallback batch at the cap (2^fallback_doublings ×
  /// fallback_sweeps, fallback_doublings ≥ 1) that left ‖H‖∞ above this fraction of its value
  /// before the batch (dimensionless, in (0, 1]; default 0: never). Further batches would
  /// repeat that one: PGS in its slow regime, while a caller with a better fallback (the
  /// proximal route's larger shift) converges sooner.
  double fallback_cap_fall = 0;
  /// Halvings of the step length α before the line search fails (α ≥ 2^−max_backtracks; default 10).
  int max_backtracks = 10;
  /// Levenberg–Marquardt damping: after a failed line search ρ grows 100-fold and the direction
  /// is recomputed, up to ρ = max_damping·max_i A_ii (default 1e2); after a full step
  /// ρ shrinks 10-fold back towards regularization·max_i A_ii.
  double max_damping = 1e2;
  /// Armijo constant σ: accept α when ½‖H(λ_α)‖² ≤ (1 − 2σα)·½‖H(λ)‖² (default 1e-4).
  double armijo = 1e-4;
  /// Non-monotone line search: the Armijo test compares against the largest ½‖H‖² of the last
  /// this many iterates (and the current one) instead of the current one alone (default 0:
  /// monotone). Where a full semismooth step switches modes the non-smooth merit can rise for an
  /// iteration and fall after; the monotone test fails there and damps the free block (a new
  /// direction, often a refactorisation). After this many iterations without a new best
  /// residual (a watchdog) the iterate goes back to the best one and the search stays monotone
  /// until it finds a new best. The returned λ is still the best iterate.
  int nonmonotone_window = 0;
  /// With sliding friction coupled: false = GMRES preconditioned with the CHOLMOD factor of
  /// the symmetric part (default); true = factorise the exact non-symmetric Newton matrix by
  /// Eigen's SparseLU, analysed afresh each time (GMRES only if that fails); faster where
  /// many contacts slide (docs/solvers.md "What limits newton-sparse").
  bool coupled_lu = false;
  /// GMRES for the friction coupling: restart length, iteration cap per Newton step and the
  /// relative residual it stops at (defaults 30, 120, 1e-12).
  int krylov_restart = 30;
  int krylov_max = 120;
  double krylov_tolerance = 1e-12;
  /// Inexact Newton (Eisenstat–Walker style forcing): GMRES stops at the relative residual
  /// η_k = max(krylov_tolerance, min(krylov_forcing, ‖H(λ_k)‖₂ / ‖H(λ⁰)‖₂)) instead of
  /// krylov_tolerance (dimensionless, default 1e-2; 0 = always krylov_tolerance). Far from the
  /// solution a direction with ‖K Δ + H‖ ≤ η‖H‖, η < 1, is still a descent direction of ½‖H‖²;
  /// η_k → 0 with the residual keeps the local convergence superlinear. On impact (250 bodies,
  /// from builtin) it halved GMRES iterations and time per step at equal Newton iterations.
  double krylov_forcing = 1e-2;
  /// true: CHOLMOD (simplicial or supernodal, CHOLMOD chooses); false: Eigen's SimplicialLDLT,
  /// the fallback CHOLMOD also falls back to when it reports a non-positive pivot (default true).
  bool cholmod = true;
  /// false: CHOLMOD's simplicial LDLᵀ (no BLAS); true: CHOLMOD picks supernodal LLᵀ (BLAS)
  /// where the fill favours it (default false: a threaded BLAS stalls on a loaded machine).
  bool supernodal = false;
  /// Keep CHOLMOD's symbolic analysis while the pattern of A is unchanged (default true).
  bool reuse_analysis = true;
  /// Consecutive iterations without a new best residual before the solve stops as Failed
  /// (default 20).
  int max_stalls = 20;
  /// Called after every iteration with the iteration count and the iterate; returning true ends
  /// the solve there (status by the usual rule on the returned best iterate; default none). The
  /// proximal-point route stops its inner solve once an iterate meets the ORIGINAL problem's
  /// target (ProximalPointDef::stop_at_target).
  std::function<bool(int iteration, const Eigen::VectorXd& lambda)> stop_when;
  /// Stale factor: a Newton direction is first sought by GMRES on the full Newton system,
  /// preconditioned with the factor kept from an earlier iteration (or an earlier solve of this
  /// object on a matrix of the same pattern, e.g. the next shift of the proximal-point route),
  /// for at most this many iterations, and the free block is refactorised only when GMRES has
  /// not met its tolerance by then (default 0: factorise at every iteration). The system differs
  /// from the factorised one by the rows that changed mode, the coupled friction rows and the
  /// change of ρ and of A's diagonal, so GMRES needs about as many iterations as that rank.
  int stale_factor_iterations = 0;
  /// A stale-factor GMRES run that ends at the cap above its tolerance η still gives the
  /// direction when its relative residual is at most this multiple of η (dimensionless ≥ 1;
  /// default 1: only runs that met η). The run's iterate is an inexact Newton direction like
  /// the others, a little less accurate; the line search judges it. Refactorising instead costs
  /// a factorisation and a GMRES run with the fresh factor (from the capped run's answer), which
  /// on contact problems with many sliding rows (the coupling the factor leaves out) still takes
  /// several iterations.
  double stale_accept = 1.0;
  /// GMRES's inner products as eight interleaved partial sums in a fixed order instead of one
  /// index-order sum (default false). Both give the same bits in every build; the lanes are
  /// several times faster on long vectors (GMRES's Gram–Schmidt is much of a Krylov direction's
  /// time on large problems) but round differently, so the iterates differ at round-off.
  bool lane_dot = false;
};

/// Work and time of one solve [ms are wall-clock, single thread].
struct NewtonSparseStats {
  int iterations = 0;         ///< Newton iterations (directions computed)
  int full_steps = 0;         ///< steps accepted with α = 1
  int line_search_trials = 0; ///< merit evaluations inside line searches
  int failed_line_searches = 0;
  int dampings = 0;           ///< ρ increases after failed line searches
  int pgs_sweeps = 0;         ///< smoothing and fallback sweeps
  int analyses = 0;           ///< symbolic analyses (ordering + symbolic factor)
  int factorizations = 0;     ///< numeric factorisations
  int fallback_factorizations = 0;  ///< of those, by SimplicialLDLT / SparseLU instead of CHOLMOD
  int lu_factorizations = 0;  ///< of those, sparse LU of the coupled system (coupled_lu)
  int krylov_iterations = 0;  ///< GMRES iterations in all (0 without sliding friction coupling)
  int stale_directions = 0;   ///< directions by GMRES with a stale factor (stale_factor_iterations)
  double analyze_ms = 0, factor_ms = 0, solve_ms = 0, total_ms = 0;
};

class NewtonSparseSolver final : public LcpSolver {
 public:
  explicit NewtonSparseSolver(const NewtonSparseDef& def = {});
  ~NewtonSparseSolver() override;
  [[nodiscard]] std::string name() const override { return "newton-sparse"; }
  [[nodiscard]] SolveResult solve(const LcpProblem& problem, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& options) override;
  /// Statistics of the last solve of this object; called from options.on_checkpoint during a
  /// solve, the counts so far (total_ms is set at the end).
  [[nodiscard]] NewtonSparseStats last_stats() const;

 private:
  struct State;  // the cached symbolic analysis and the last statistics (one solve at a time)
  NewtonSparseDef def_;
  std::unique_ptr<State> state_;
};

std::unique_ptr<LcpSolver> make_newton_sparse(const NewtonSparseDef& def = {});

}  // namespace dc
