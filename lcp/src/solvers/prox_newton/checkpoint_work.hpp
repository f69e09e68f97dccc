#pragma once
// prox-newton's work at a checkpoint (ProxNewtonSolver::checkpoint_stats): the solve's statistics
// when the caller's on_checkpoint sees an iterate, the part still in progress included (the lead
// stage's nncg run, a newton-sparse or proximal-point finish, the safeguard's nncg run, which add their counts to the
// solve's statistics only when they return).
#include <Eigen/Core>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "dc/lcp/proximal_point.hpp"

namespace dc::solvers::prox {

/// A part that calls checkpoints at its own iteration count: what those iterations are, and
/// where its factorisations so far are read.
struct InFlightPart {
  enum class Kind { Lead, NewtonSparse, ProximalPoint, Safeguard };
  Kind kind = Kind::Lead;
  const NewtonSparseSolver* finish = nullptr;  ///< NewtonSparse: its last_stats() count during a solve
  const ProximalPointStats* route = nullptr;   ///< ProximalPoint: filled as its outer iterations end

  /// nncg sweeps, no factorisation.
  static InFlightPart lead() { return {}; }
  /// nncg sweeps of the safeguard (safeguard_sweeps), no factorisation.
  static InFlightPart safeguard() { return {Kind::Safeguard, nullptr, nullptr}; }
  /// Newton iterations of the hard problem (finish_newton).
  static InFlightPart newton_sparse(const NewtonSparseSolver& s) { return {Kind::NewtonSparse, &s, nullptr}; }
  /// Newton iterations of the proximal-point route (finish_newton, proximal_finish_newton).
  static InFlightPart proximal_point(const ProximalPointStats& ps) { return {Kind::ProximalPoint, nullptr, &ps}; }
};

/// Writes the work so far to `at` each time the caller's on_checkpoint is about to be called.
class CheckpointWork {
 public:
  /// `st`: the solve's statistics as they grow; `at`: the snapshot the caller reads.
  CheckpointWork(const ProxNewtonStats& st, ProxNewtonStats& at) : st_(st), at_(at) {}
  CheckpointWork(const CheckpointWork&) = delete;
  CheckpointWork& operator=(const CheckpointWork&) = delete;

  /// `o` with its on_checkpoint (when set) preceded by the snapshot. The copy refers to this
  /// object: it must not outlive it.
  [[nodiscard]] SolverOptions watch(const SolverOptions& o) {
    SolverOptions w = o;
    if (o.on_checkpoint)
      w.on_checkpoint = [this, user = o.on_checkpoint](int k, const Eigen::VectorXd& lambda) {
        snapshot();
        user(k, lambda);
      };
    return w;
  }

  /// A checkpoint of `part` at its own iteration `iterations` (the checkpoint's number: past the
  /// part's last iteration when it passes its remaining checkpoints its final λ) is on its way
  /// to the caller.
  void begin(const InFlightPart& part, int iterations) {
    part_ = part;
    iterations_ = iterations;
    active_ = true;
  }
  void end() { active_ = false; }

 private:
  void snapshot() {
    at_ = st_;
    if (!active_) return;
    switch (part_.kind) {
      case InFlightPart::Kind::Lead:
        at_.lead_sweeps += iterations_;
        break;
      case InFlightPart::Kind::NewtonSparse: {
        const NewtonSparseStats ns = part_.finish->last_stats();  // its counts so far
        at_.finish_newton += ns.iterations;
        at_.factorizations += ns.factorizations;
        break;
      }
      case InFlightPart::Kind::Safeguard:
        at_.safeguard_sweeps += iterations_;
        break;
      case InFlightPart::Kind::ProximalPoint:
        at_.finish_newton += iterations_;
        at_.proximal_finish_newton += iterations_;
        at_.factorizations += part_.route->factorizations;
        break;
    }
  }

  const ProxNewtonStats& st_;
  ProxNewtonStats& at_;
  InFlightPart part_;
  int iterations_ = 0;
  bool active_ = false;
};

}  // namespace dc::solvers::prox
