#pragma once
// One interface for every LCP solver variant. Input: the problem (A, b, bounds), an initial
// guess λ⁰ (the warm start) and options. Output: λ, a status that says what happened, the
// number of sweeps, the per-sweep convergence measure θ_k = max_i |λ_i^k − λ_i^{k−1}| and
// the final natural-map residual. No solver loops forever or returns NaN: a solver that
// cannot make progress says so in `status` and returns its last finite iterate. `converged`
// is a checked fact about the returned λ, never a stopping rule (solution_target).
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "dc/core/thread_pacer.hpp"
#include "dc/lcp/lcp_problem.hpp"

namespace dc {

/// The outcome of a solve. Every solver's status is decided by one shared rule
/// (lcp/src/solvers/solver_common.hpp, decide_status): `Converged` only when the returned λ
/// passes the solution test natural_residual(p, λ) ≤ solution_target(p, options).
/// The integer values are stored in trajectory files (/solver/status): append, never renumber.
enum class SolveStatus {
  Converged,     ///< the solution test holds on the returned λ (whatever stopped the method)
  SweepLimit,    ///< ran the maximum number of sweeps without meeting the tolerance
                 ///< (the normal outcome in fixed-sweep mode, tolerance = 0)
  Diverged,      ///< iterates became non-finite or grew without bound; λ is the last finite iterate
  Infeasible,    ///< proved to have no solution (verified Farkas certificate or exhaustive
                 ///< enumeration; docs/lcp.md), never merely because a method gave up
  Failed,        ///< the method broke down (singular pivot, line search failure, ...)
  InvalidInput,  ///< the problem violates LcpProblem::validate or the solver's requirements
  /// The stopping rule the caller set held (θ_k ≤ tolerance for the sweep methods, residual
  /// ≤ tolerance [N] for newton-sparse and the proximal route) but the solution test does
  /// not: the run ended where asked, and λ is not claimed to be a solution.
  ToleranceReached,
};
const char* to_string(SolveStatus s);
/// True for the statuses of a run that stopped on its tolerance: Converged or ToleranceReached
/// (the bench's sweeps-to-tol protocol and simulate's "reached the tolerance" count).
bool stopped_at_tolerance(SolveStatus s);

struct SolverOptions {
  int max_sweeps = 3000;     ///< sweep (iteration) limit
  double tolerance = 0.0;    ///< stop when θ_k ≤ tolerance; 0 = fixed-sweep mode
  double omega = 1.0;        ///< relaxation (psor, pgs-colored; 1 = Gauss–Seidel); jacobi uses it as damping
  /// "pgs" only: solve the two normal rows of each two-point manifold (two contacts of one
  /// body pair with one normal, e.g. a box face on a face) as one 2 × 2 LCP, exactly, like
  /// Box2D's block solver (lcp/src/solvers/pgs_manifold_block.hpp; docs/lcp.md). false =
  /// the row-by-row order of every row (for comparison).
  /// Problems without such manifolds (circle scenes) give the same iterates either way.
  bool block_manifolds = true;
  bool record_theta = true;  ///< fill SolveResult::theta (one entry per sweep)
  /// "pgs-colored" only: symmetric Gauss–Seidel, every second sweep visits the colours in
  /// reverse order (last colour first), so a sweep pair carries a load through a pile both ways
  /// along the colour order (a forward sweep carries it to later colours in one sweep, to
  /// earlier ones one colour per sweep). Same fixed points; the sweeps then run on one thread.
  /// false (the default): every sweep in colour order.
  bool symmetric = false;
  /// The solution test every `Converged` passes, relative to the problem's scale:
  /// natural_residual ≤ exact_tolerance·‖b‖∞ (solution_target). The exact methods iterate to it.
  double exact_tolerance = 1e-9;
  /// Sweeps after which `on_checkpoint` is called with the current iterate (sorted, ≥ 1).
  /// Used by the bench to sample the speed/accuracy trade in one run; empty = never.
  std::vector<int> checkpoints;
  std::function<void(int sweep, const Eigen::VectorXd& lambda)> on_checkpoint;
};

struct SolveResult {
  Eigen::VectorXd lambda;
  SolveStatus status = SolveStatus::Failed;
  int sweeps = 0;                 ///< sweeps (or pivots / Newton iterations) performed
  std::vector<double> theta;      ///< θ_k for k = 1..sweeps (when recorded)
  double residual = 0.0;          ///< natural_residual at the returned λ
  std::string message;            ///< human-readable detail for non-converged statuses
};

/// The solution test's target [units of the natural residual]: options.exact_tolerance·‖b‖∞
/// (‖b‖∞ at least the smallest normal double). ‖b‖∞ is the natural residual of λ = 0 (for
/// rows whose bounds contain 0), so the test asks for a reduction by exact_tolerance from
/// the trivial guess, whatever the units or the scale of A and b. A solver returns Converged
/// only when natural_residual(problem, λ) ≤ this value.
double solution_target(const LcpProblem& problem, const SolverOptions& options);

/// A solver object may keep reusable state between solves (pgs-colored: the previous colouring
/// and its buffers; newton-sparse: the symbolic analysis), so `solve` is not const: use one
/// solver object per thread (make_solver makes a fresh one).
class LcpSolver {
 public:
  virtual ~LcpSolver() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  /// True when the solver needs LcpProblem::J (matrix-free variants).
  [[nodiscard]] virtual bool needs_jacobian() const { return false; }
  /// True when the solver works on A = J M⁻¹ Jᵀ Δt: callers that solve an assembled problem
  /// repeatedly call LcpProblem::ensure_assembled_matrix() first (World::step and the bench
  /// do); handed a problem without A, such a solver forms it for that solve only.
  [[nodiscard]] virtual bool needs_assembled_matrix() const { return true; }
  [[nodiscard]] virtual SolveResult solve(const LcpProblem& problem, const Eigen::VectorXd& lambda0,
                                          const SolverOptions& options) = 0;
  /// solve() into storage the caller keeps from solve to solve: λ into `lambda` (resized to the
  /// rows: a KeptVector reallocates only past its capacity), the rest of the outcome into
  /// `result` (its lambda left empty), from λ⁰ given as any contiguous vector (a KeptVector, a
  /// VectorXd; empty: zeros). The same λ and outcome as solve(). The default calls solve() and
  /// copies λ; pgs-colored writes λ in place and reads λ⁰ where it lies, so that a step of a
  /// World whose row count changes allocates nothing in its solve.
  virtual void solve_into(const LcpProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& lambda0,
                          const SolverOptions& options, KeptVector& lambda, SolveResult& result);
  /// Threads this solver's solves use where they pay (pgs-colored: its `threads`, 0 resolved to
  /// OpenMP's default, once its threaded solves have paid or when forced; 1 for the others).
  /// World::step runs its other stages on as many while whole steps pay.
  [[nodiscard]] virtual int threads() const { return 1; }
  /// Threads this solver's solves could use (pgs-colored: its `threads`, 0 resolved to
  /// OpenMP's default, whether or not they have paid yet; 1 for the others). World::step paces
  /// whole steps on as many (lead_threads).
  [[nodiscard]] virtual int thread_capacity() const { return threads(); }
  /// The next solves run on one thread (true) or as the solver chooses (false): World::step's
  /// pacer runs whole steps serially while threaded steps do not pay. Never changes a result.
  virtual void hold_threads(bool serial) { (void)serial; }
  /// While led (true), the caller paces: a solve not held (hold_threads) runs on the solver's
  /// threads wherever its size rule allows, set-up included, and the solver's own pacer
  /// neither chooses nor records it. World::step leads the solver during a step, so that one
  /// pacer judges the whole step, threaded against serial. Never changes a result.
  virtual void lead_threads(bool led) { (void)led; }
  /// True when the solver's threads are forced rather than paced (pgs-colored with
  /// min_batches_per_thread = 0): World::step then runs every large enough step on them.
  [[nodiscard]] virtual bool threads_forced() const { return false; }
  /// The pacer of the whole steps that lead this solver (World::step), made with ratio `pays`
  /// on the first call and kept by the solver, so that what it learned outlives one World: a
  /// World made afresh for a few steps (a short scene, a benchmark's round) starts from the
  /// verdict and backoff of the steps before it instead of probing the threads again from its
  /// first step (on a pile where threads do not pay, each probe is a slower step). The pacer
  /// compares time per unit of work, so Worlds of other sizes stepped with this solver share
  /// it. nullptr (the default): each World paces its steps with a pacer of its own.
  [[nodiscard]] virtual ThreadPacer* step_pacer(double pays) {
    (void)pays;
    return nullptr;
  }
};

/// The LCP solvers make_solver builds; each has one spelling (solver_names, SolverId::parse).
enum class SolverKind {
  Pgs,           ///< "pgs": matrix-free PGS on body velocities (the engine default)
  PgsColored,    ///< "pgs-colored": colour-ordered PGS, SIMD batches of 8 contacts (pgs_colored.hpp)
  PgsAssembled,  ///< "pgs-assembled": PGS on the sparse A (the seed's form)
  Psor,          ///< "psor"
  Jacobi,        ///< "jacobi"
  Lemke,         ///< "lemke": exact pivoting, standard LCPs
  Newton,        ///< "newton": minimum-map Newton, box bounds and friction
  NewtonSparse,  ///< "newton-sparse": semismooth Newton, CHOLMOD (newton_sparse.hpp)
  Nncg,          ///< "nncg": pgs's sweeps with nonlinear conjugate-gradient momentum and restarts
  ProxNewton,    ///< "prox-newton": proximal Newton on convex frozen-friction subproblems (prox_newton.hpp)
  NncgColored,   ///< "nncg-colored": nncg's momentum on pgs-colored's sweeps (pgs_colored.hpp)
};
/// The spelling of `kind` ("pgs", "pgs-colored", …, the entries of solver_names()).
const char* to_string(SolverKind kind);

/// The sweep kernel of pgs-colored (all give the same iterates bit for bit; pgs_colored.hpp).
enum class PgsColoredKernel {
  Auto,    ///< AVX2 (+ FMA) on AMD CPUs (at least as fast there: Zen runs 512-bit
           ///< operations as two halves), else AVX-512 if present, else AVX2, else scalar
  Avx512,  ///< AVX-512 F/DQ/VL: 8 lanes per register
  Avx2,    ///< AVX2 + FMA: 4 lanes per register, two per batch
  Scalar,  ///< one lane at a time (portable)
};

/// A solver as a value: its kind and, for pgs-colored, the threads and kernel its name may
/// spell ("pgs-colored:N" with N ≥ 1 OpenMP threads, "pgs-colored:N:K" with kernel K = auto,
/// avx512, avx2 or scalar). Names are read once, where users give them (scene files, CLI
/// options, Python), by parse; to_string gives back the spelling parse read.
struct SolverId {
  SolverKind kind = SolverKind::Pgs;
  /// PgsColored only: the threads N of "pgs-colored:N" (≥ 1); 0 = not spelled ("pgs-colored",
  /// which runs one thread).
  int threads = 0;
  /// PgsColored with threads only: the kernel K of "pgs-colored:N:K"; empty = not spelled (Auto).
  std::optional<PgsColoredKernel> kernel;

  constexpr SolverId() = default;
  /// The solver `k`, with pgs-colored's threads `n` and kernel `kernel_k` as parse reads them.
  constexpr explicit SolverId(SolverKind k, int n = 0, std::optional<PgsColoredKernel> kernel_k = std::nullopt)
      : kind(k), threads(n), kernel(kernel_k) {}

  /// Reads a name. Throws ConfigError "unknown LCP solver '<name>' (valid: <solver_names()>)",
  /// or "LCP solver '<name>': expected pgs-colored:<threads>[:<kernel>], …" for a malformed
  /// pgs-colored suffix.
  static SolverId parse(std::string_view name);

  friend bool operator==(const SolverId&, const SolverId&) = default;
};
/// The name parse reads back to `id` (parse(to_string(id)) == id).
std::string to_string(const SolverId& id);

/// The solver `id` names (SolverKind). pgs-colored with threads/kernel: PgsColoredDef with
/// them; throws ConfigError "LCP solver '<name>': this CPU cannot run the <K> kernel" for a
/// kernel pgs_colored_kernel_available refuses.
std::unique_ptr<LcpSolver> make_solver(const SolverId& id);
/// make_solver(SolverId::parse(name)): the same ConfigErrors as parse for an unknown name.
std::unique_ptr<LcpSolver> make_solver(std::string_view name);
/// The spellings of every SolverKind, in enum order (the list error messages name).
std::vector<std::string> solver_names();

}  // namespace dc
