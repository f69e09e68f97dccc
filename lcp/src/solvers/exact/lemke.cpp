// "lemke": Lemke's complementary pivoting for the standard LCP
//     w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0        (M = A, q = b; all lo = 0, hi = ∞).
// Scaling: M̃ = S M S, q̃ = S q, S = diag(1/√M_ii) (1 where M_ii ≤ 0), z = S z̃, then M̃/‖M̃‖max,
// q̃/‖q̃‖∞. First attempt: lemke_pivoting.hpp with covering vector d = 1 (cap 50·n + 10); when
// z₀ leaves, an LU solve of M_SS z_S = −q_S plus two refinement steps, then a newton polish if
// max_i |min(z_i, w_i)| > exact_tolerance·max(1, ‖q‖∞). Converged only when that residual, on the
// original problem, is within the tolerance. A ray proves nothing (Lemke also rays out on
// solvable problems), so on no verified solution it goes on, in order: a Farkas certificate
// (lcp_proofs.hpp, n ≤ 500) → Infeasible; three other covering vectors; n ≤ 16: the 2ⁿ
// complementary bases (a proof either way); n ≤ 200: newton from four deterministic starts;
// else Failed, naming the attempts. `sweeps` counts all pivots plus newton iterations.
#include <Eigen/Dense>
#include <cmath>
#include <cstdint>
#include <limits>

#include "solvers/exact/lcp_proofs.hpp"
#include "solvers/exact/lemke_pivoting.hpp"
#include "dc/core/number_text.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc::solvers {
namespace {

constexpr int kNewtonFallbackMaxN = 200;

/// splitmix64 in [lo, hi): the deterministic covering vectors and starts (no global state).
class Mix {
 public:
  explicit Mix(uint64_t seed) : s_(seed) {}
  double uniform(double lo, double hi) {
    uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return lo + (hi - lo) * static_cast<double>(z >> 11) * 0x1.0p-53;
  }

 private:
  uint64_t s_;
};

/// The scaled problem and the map back: z = S z'·qscale/mscale.
struct Scaled {
  Eigen::VectorXd S;
  Eigen::MatrixXd M;  ///< S A S / mscale
  Eigen::VectorXd q;  ///< S b / qscale
  double mscale = 1.0, qscale = 1.0;
  [[nodiscard]] Eigen::VectorXd original(const Eigen::VectorXd& zs) const {
    return S.cwiseProduct(zs.cwiseMax(0.0)) * (qscale / mscale);
  }
};

Scaled scale(const LcpProblem& p) {
  const int n = p.rows();
  Scaled s;
  s.S.resize(n);
  for (int i = 0; i < n; ++i) {
    const double d = p.A.coeff(i, i);
    s.S[i] = (d > 0 && std::isfinite(1.0 / std::sqrt(d))) ? 1.0 / std::sqrt(d) : 1.0;
  }
  const Eigen::MatrixXd M = s.S.asDiagonal() * Eigen::MatrixXd(p.A) * s.S.asDiagonal();
  const Eigen::VectorXd q = s.S.cwiseProduct(p.b);
  const double mmax = M.cwiseAbs().maxCoeff();
  s.mscale = (mmax > 0 && std::isfinite(mmax)) ? mmax : 1.0;
  const double qmax = q.cwiseAbs().maxCoeff();
  s.qscale = (qmax > 0 && std::isfinite(qmax)) ? qmax : 1.0;
  s.M = M / s.mscale;
  s.q = q / s.qscale;
  return s;
}

/// One Lemke run with covering vector d, then refinement; `z`/`res` get the best point.
struct Attempt {
  bool solved = false;  ///< verified: residual ≤ target
  Eigen::VectorXd z;
  double res = std::numeric_limits<double>::infinity();
  int pivots = 0, newton_steps = 0;
  std::string why;  ///< how the pivoting ended
  bool polished = false;
};

Attempt attempt(const LcpProblem& p, const Scaled& s, const Eigen::VectorXd& d, double target,
                const SolverOptions& o) {
  const int n = p.rows();
  Attempt a;
  const LemkePivoting lp = lemke_pivoting(s.M, s.q, d, 50 * n + 10);
  a.pivots = lp.pivots;
  a.why = lp.why;
  if (lp.outcome != LemkePivoting::Outcome::Solved) return a;
  a.z = s.original(lp.z);
  a.res = natural_residual(p, a.z);
  if (const int m = static_cast<int>(lp.active.size()); m > 0) {  // refine on the active set
    Eigen::MatrixXd Mss(m, m);
    Eigen::VectorXd qs(m);
    for (int i = 0; i < m; ++i) {
      qs[i] = -s.q[lp.active[static_cast<size_t>(i)]];
      for (int j = 0; j < m; ++j) Mss(i, j) = s.M(lp.active[static_cast<size_t>(i)], lp.active[static_cast<size_t>(j)]);
    }
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(Mss);
    Eigen::VectorXd zs = lu.solve(qs);
    for (int step = 0; step < 2; ++step) zs += lu.solve(qs - Mss * zs);
    if (zs.allFinite()) {
      Eigen::VectorXd full = Eigen::VectorXd::Zero(n);
      for (int i = 0; i < m; ++i) full[lp.active[static_cast<size_t>(i)]] = zs[i];
      const Eigen::VectorXd zr = s.original(full);
      if (const double rr = natural_residual(p, zr); rr < a.res) {
        a.res = rr;
        a.z = zr;
      }
    }
  }
  if (!(a.res <= target)) {
    SolverOptions po;
    po.exact_tolerance = o.exact_tolerance;
    po.record_theta = false;
    po.max_sweeps = 200;
    const SolveResult polished = newton_solve(p, a.z, po, false);
    a.newton_steps = polished.sweeps;
    if (polished.residual < a.res) {
      a.res = polished.residual;
      a.z = polished.lambda;
      a.polished = true;
    }
  }
  a.solved = a.res <= target;
  if (!a.solved)
    a.why = "complementarity error " + g_text(a.res) + " above tolerance " + g_text(target) +
            " after refinement";
  return a;
}

class LemkeSolver final : public LcpSolver {
 public:
  [[nodiscard]] std::string name() const override { return "lemke"; }
  [[nodiscard]] SolveResult solve(const LcpProblem& problem, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& o) override {
    std::optional<LcpProblem> local;
    const LcpProblem& p = with_assembled_matrix(problem, local);
    Eigen::VectorXd lambda;
    if (auto bad = check_input(p, lambda0, name(), lambda)) return *bad;
    const int n = p.rows();
    if (const int i = first_nonstandard_row(p); i >= 0) {
      SolveResult r;
      r.status = SolveStatus::InvalidInput;
      r.lambda = lambda;
      r.message = "lemke: row " + std::to_string(i) +
                  " is not a standard LCP row (needs lo = 0, hi = inf, no friction); use newton";
      finish(p, r, o, StopRule::Solution);
      return r;
    }
    SolveResult r;
    const double target = solution_target(p, o);
    CheckpointCursor cp(o);
    auto done = [&](SolveStatus status, const Eigen::VectorXd& z, std::string message) {
      r.status = status;
      r.lambda = z;
      r.message = std::move(message);
      if (status == SolveStatus::Converged) cp.flush_final(z);
      finish(p, r, o, StopRule::Solution);
      return r;
    };
    if (n == 0 || p.b.minCoeff() >= 0) return done(SolveStatus::Converged, Eigen::VectorXd::Zero(n), "");

    const Scaled s = scale(p);
    const Attempt first = attempt(p, s, Eigen::VectorXd::Ones(n), target, o);
    r.sweeps = first.pivots + first.newton_steps;
    if (first.solved) return done(SolveStatus::Converged, first.z, first.polished ? "lemke: refined by newton polish" : "");

    // No verified solution: prove infeasibility or find a solution another way.
    std::string head = "lemke: covering vector 1: " + first.why;
    if (first.why.rfind("ray", 0) == 0) head += " (proves nothing unless M is copositive-plus)";
    Eigen::VectorXd best = first.z.size() == n ? first.z : Eigen::VectorXd::Zero(n);
    double best_res = first.z.size() == n ? first.res : natural_residual(p, best);

    const FarkasCertificate cert = find_farkas_certificate(s.M, s.q);
    if (cert.found) {
      std::string detail;  // the certificate for the scaled problem is S⁻¹-scaled for the original
      if (check_farkas_certificate(Eigen::MatrixXd(p.A), Eigen::VectorXd(p.b), s.S.cwiseProduct(cert.y), detail))
        return done(SolveStatus::Infeasible, Eigen::VectorXd::Zero(n), head + "; infeasible: " + detail);
    }
    std::string tried = cert.detail;

    Mix mix(0x5eed1e3eull + static_cast<uint64_t>(n));
    std::string covering;
    for (int k = 0; k < 3; ++k) {
      Eigen::VectorXd d(n);
      for (int i = 0; i < n; ++i) d[i] = mix.uniform(0.1, 1.0);
      const Attempt a = attempt(p, s, d, target, o);
      r.sweeps += a.pivots + a.newton_steps;
      if (a.solved)
        return done(SolveStatus::Converged, a.z,
                    head + "; solved with random covering vector " + std::to_string(k + 1));
      if (a.z.size() == n && a.res < best_res) {
        best_res = a.res;
        best = a.z;
      }
      covering += (k ? ", " : "") + a.why;
    }
    tried += "; 3 other covering vectors (" + covering + ")";

    if (n <= kEnumerateMaxN) {
      const BasisEnumeration e = enumerate_complementary_bases(s.M, s.q, [&](const Eigen::VectorXd& zs) {
        const Eigen::VectorXd z = s.original(zs);
        return natural_residual(p, z) <= target;
      });
      if (e.solved) return done(SolveStatus::Converged, s.original(e.z), head + "; " + e.detail);
      if (e.proves_none)
        return done(SolveStatus::Infeasible, Eigen::VectorXd::Zero(n), head + "; " + cert.detail + "; infeasible: " + e.detail);
      tried += "; " + e.detail;
    }

    if (n <= kNewtonFallbackMaxN) {
      SolverOptions no;
      no.exact_tolerance = o.exact_tolerance;
      no.record_theta = false;
      no.max_sweeps = 500;
      double newton_best = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 4; ++k) {
        Eigen::VectorXd start = Eigen::VectorXd::Zero(n);
        if (k == 1) start = s.original(Eigen::VectorXd::Ones(n));
        if (k >= 2)
          for (int i = 0; i < n; ++i) start[i] = s.S[i] * mix.uniform(0, 2) * (s.qscale / s.mscale);
        const SolveResult nr = newton_solve(p, start, no, false);
        r.sweeps += nr.sweeps;
        if (nr.status == SolveStatus::Converged)
          return done(SolveStatus::Converged, nr.lambda, head + "; solved by newton from start " + std::to_string(k + 1));
        newton_best = std::min(newton_best, nr.residual);
        if (nr.residual < best_res) {
          best_res = nr.residual;
          best = nr.lambda;
        }
      }
      tried += "; newton from 4 starts (best residual " + g_text(newton_best) + ")";
    }
    return done(SolveStatus::Failed, best, head + "; no solution and no proof of infeasibility: " + tried);
  }
};

}  // namespace

std::unique_ptr<LcpSolver> make_lemke() { return std::make_unique<LemkeSolver>(); }

}  // namespace dc::solvers
