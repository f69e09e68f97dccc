#include "solvers/solver_common.hpp"

#include <cstdio>
#include <limits>
#include <stdexcept>

#include "dc/core/error.hpp"

namespace dc::solvers {

const LcpProblem& with_assembled_matrix(const LcpProblem& p, std::optional<LcpProblem>& local) {
  if (p.has_assembled_matrix() || !p.has_jacobian()) return p;
  local.emplace(p);
  local->ensure_assembled_matrix();
  return *local;
}

double rhs_scale(const LcpProblem& p) {
  double s = 1.0;
  for (int i = 0; i < p.b.size(); ++i) s = std::max(s, std::abs(p.b[i]));
  return s;
}

int first_nonstandard_row(const LcpProblem& p) {
  for (int i = 0; i < p.rows(); ++i)
    if (p.is_friction_row(i) || p.lo[i] != 0.0 || p.hi[i] != std::numeric_limits<double>::infinity()) return i;
  return -1;
}

std::optional<SolveResult> check_input(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda0,
                                       const std::string& solver, Eigen::VectorXd& lambda) {
  const int n = p.rows();
  auto invalid = [&](const std::string& msg) {
    SolveResult r;
    r.status = SolveStatus::InvalidInput;
    r.lambda = Eigen::VectorXd::Zero(std::max(0, n));
    if (lambda0.size() == n && lambda0.allFinite()) r.lambda = lambda0;
    r.message = solver + ": " + msg;
    r.residual = std::numeric_limits<double>::infinity();
    return r;
  };
  try {
    p.validate();
  } catch (const InvalidArgument& e) {
    return invalid(e.what());
  }
  if (lambda0.size() == 0) {
    lambda = Eigen::VectorXd::Zero(n);
  } else if (lambda0.size() != n) {
    return invalid("initial guess has " + std::to_string(lambda0.size()) + " entries, the problem " +
                   std::to_string(n) + " rows");
  } else if (!lambda0.allFinite()) {
    return invalid("initial guess has a non-finite entry");
  } else {
    lambda = lambda0;
  }
  return std::nullopt;
}

SolveStatus decide_status(const LcpProblem& p, double residual, SolveStatus provisional, StopRule rule,
                          const SolverOptions& o) {
  switch (provisional) {
    case SolveStatus::Converged:  // (the target, a pass over b, only where it decides)
      if (residual <= solution_target(p, o)) return SolveStatus::Converged;  // false for NaN
      return rule == StopRule::Tolerance ? SolveStatus::ToleranceReached : SolveStatus::Failed;
    default: return provisional;
  }
}

void finish(const LcpProblem& p, SolveResult& r, const SolverOptions& o, StopRule rule) {
  if (!r.lambda.allFinite()) {
    // Defensive: a solver must never hand back NaN/Inf. Replace by zero and say so.
    r.lambda = Eigen::VectorXd::Zero(p.rows());
    if (r.status == SolveStatus::Converged || r.status == SolveStatus::SweepLimit)
      r.status = SolveStatus::Failed;
    r.message += (r.message.empty() ? "" : "; ") + std::string("non-finite solution replaced by zero");
  }
  r.residual = natural_residual(p, r.lambda);
  settle_status(p, r, o, rule);
}

void settle_status(const LcpProblem& p, SolveResult& r, const SolverOptions& o, StopRule rule) {
  const SolveStatus claimed = r.status;
  r.status = decide_status(p, r.residual, claimed, rule, o);
  if (claimed == SolveStatus::Converged && r.status != SolveStatus::Converged) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s; natural residual %.3g above the solution target %.3g",
                  rule == StopRule::Tolerance ? "stopped at the tolerance" : "no verified solution", r.residual,
                  solution_target(p, o));
    r.message += (r.message.empty() ? "" : "; ") + std::string(buf);
  }
}

RowBounds::RowBounds(const LcpProblem& p) {
  const int n = p.rows();
  lo_fixed.resize(static_cast<size_t>(n));
  hi_fixed.resize(static_cast<size_t>(n));
  mu.resize(static_cast<size_t>(n));
  coupled.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const auto u = static_cast<size_t>(i);
    if (p.is_friction_row(i)) {
      lo_fixed[u] = 0.0;
      hi_fixed[u] = 0.0;
      mu[u] = p.mu[i];
      coupled[u] = p.normal_row[u];
    } else {
      lo_fixed[u] = p.lo[i];
      hi_fixed[u] = p.hi[i];
      mu[u] = 0.0;
      coupled[u] = i;
    }
  }
}

CheckpointCursor::CheckpointCursor(const SolverOptions& o) : o_(o) {
  if (!o.on_checkpoint) return;
  const std::vector<int>& given = o.checkpoints;
  bool increasing = given.empty() || given.front() >= 1;
  for (size_t i = 1; increasing && i < given.size(); ++i) increasing = given[i - 1] < given[i];
  if (increasing) {
    ks_ = given.data();
    size_ = given.size();
    return;
  }
  own_.reserve(given.size());
  for (int k : given)
    if (k >= 1) own_.push_back(k);
  if (!std::is_sorted(own_.begin(), own_.end())) std::sort(own_.begin(), own_.end());
  own_.erase(std::unique(own_.begin(), own_.end()), own_.end());
  ks_ = own_.data();
  size_ = own_.size();
}

void CheckpointCursor::after(int k, const Eigen::VectorXd& lambda) {
  while (next_ < size() && at(next_) < k) ++next_;
  if (next_ < size() && at(next_) == k) {
    o_.on_checkpoint(k, lambda);
    ++next_;
  }
}

void CheckpointCursor::reach(int k, const Eigen::VectorXd& lambda) {
  size_t last = next_;
  while (last < size() && at(last) <= k) ++last;
  if (last == next_) return;
  next_ = last;
  o_.on_checkpoint(at(last - 1), lambda);
}

void CheckpointCursor::flush_final(const Eigen::VectorXd& lambda) {
  for (; next_ < size(); ++next_) o_.on_checkpoint(at(next_), lambda);
}

void report_singular_rows(const LcpProblem& p, const std::vector<int>& singular, SolveResult& r) {
  if (singular.empty()) return;
  const Eigen::VectorXd w = lcp_velocity(p, r.lambda);
  const double thresh = 1e-12 * rhs_scale(p);
  std::string bad, all;
  int nbad = 0;
  for (int i : singular) {
    const double l = p.lower(i, r.lambda), h = p.upper(i, r.lambda);
    const double e = std::abs(r.lambda[i] - std::clamp(r.lambda[i] - w[i], l, std::max(l, h)));
    if (!(e <= thresh)) {
      if (nbad++ < 5) bad += (bad.empty() ? "" : ",") + std::to_string(i);
    }
    if (all.size() < 60) all += (all.empty() ? "" : ",") + std::to_string(i);
  }
  std::string msg;
  if (nbad > 0 && r.status != SolveStatus::Diverged) {
    r.status = SolveStatus::Failed;
    msg = std::to_string(nbad) + " row(s) with non-positive diagonal A_ii are not complementary (rows " +
          bad + (nbad > 5 ? ",..." : "") + "); they were moved to the bound their residual points at";
  } else {
    msg = std::to_string(singular.size()) + " row(s) with non-positive diagonal A_ii (rows " + all +
          ") were moved to the bound their residual points at, not divided by";
  }
  r.message += (r.message.empty() ? "" : "; ") + msg;
}

SolveResult refuse_matrix_free(const LcpProblem& p, Eigen::VectorXd lambda, const std::string& solver,
                               const std::string& why) {
  SolveResult r;
  r.status = SolveStatus::InvalidInput;
  r.lambda = std::move(lambda);
  r.message = solver + ": " + why + "; use pgs-assembled";
  finish(p, r, SolverOptions{}, StopRule::Solution);
  return r;
}

}  // namespace dc::solvers

namespace dc {

double solution_target(const LcpProblem& problem, const SolverOptions& options) {
  double s = std::numeric_limits<double>::min();
  for (int i = 0; i < problem.b.size(); ++i) s = std::max(s, std::abs(problem.b[i]));
  return options.exact_tolerance * s;
}

bool stopped_at_tolerance(SolveStatus s) {
  return s == SolveStatus::Converged || s == SolveStatus::ToleranceReached;
}

void LcpSolver::solve_into(const LcpProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& lambda0,
                           const SolverOptions& options, KeptVector& lambda, SolveResult& result) {
  result = solve(problem, Eigen::VectorXd(lambda0), options);
  lambda = result.lambda;
  result.lambda = Eigen::VectorXd();
}

}  // namespace dc
