// "lemke": Lemke's complementary pivoting for the standard LCP
//
//     w = M z + q,   z ≥ 0,  w ≥ 0,  zᵀw = 0        (M = A, q = b; all lo = 0, hi = ∞)
//
// on a dense tableau [ I | −M | −d | q ] with covering vector d = 1 and artificial z₀.
// Start: if q ≥ 0, z = 0 solves it (0 pivots). Otherwise z₀ enters at the row of the most
// negative q_i; then the complement of each leaving variable enters. Ratio test with
// lexicographic tie-breaking (rows of B⁻¹ divided by the pivot column entry — B⁻¹ is the
// tableau's w block), which prevents cycling on degenerate problems such as rank-deficient
// contact matrices; z₀ leaves as soon as it ties. Terminations:
//   * z₀ leaves the basis     → solution; refined (see below) → Converged / Failed
//   * no positive pivot entry → secondary ray → Infeasible (for copositive-plus M, e.g.
//                                symmetric PSD, this proves the LCP has no solution)
//   * pivot cap 50·n + 10     → Failed
// The problem is scaled first: symmetric Jacobi scaling M̃ = S M S, q̃ = S q with
// S = diag(1/√M_ii) (1 where M_ii ≤ 0) makes badly scaled problems (diagonal spanning
// 1e-4…1e4) well scaled — z = S z̃ maps solutions one to one — and then M̃/‖M̃‖max,
// q̃/‖q̃‖∞ so values near overflow do no harm.
//
// Refinement: the tableau accumulates round-off in O(n) pivots. With S = the basic z's, the
// solution satisfies M_SS z_S = −q_S, z_{S̄} = 0; one LU solve of that system plus two steps
// of iterative refinement recovers full accuracy. If the complementarity error
// max_i |min(z_i, w_i)| is still above exact_tolerance·max(1,‖q‖∞), newton polishes.
#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc::solvers {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

class LemkeSolver final : public LcpSolver {
 public:
  [[nodiscard]] std::string name() const override { return "lemke"; }
  [[nodiscard]] SolveResult solve(const LcpProblem& problem, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& o) const override {
    std::optional<LcpProblem> local;
    const LcpProblem& p = with_assembled_matrix(problem, local);
    Eigen::VectorXd lambda;
    if (auto bad = check_input(p, lambda0, name(), lambda)) return *bad;
    const int n = p.rows();
    for (int i = 0; i < n; ++i)
      if (p.is_friction_row(i) || p.lo[i] != 0.0 || p.hi[i] != kInf) {
        SolveResult r;
        r.status = SolveStatus::InvalidInput;
        r.lambda = lambda;
        r.message = "lemke: row " + std::to_string(i) +
                    " is not a standard LCP row (needs lo = 0, hi = inf, no friction); use newton";
        finish(p, r);
        return r;
      }
    SolveResult r;
    const double target = o.exact_tolerance * rhs_scale(p);
    CheckpointCursor cp(o);
    if (n == 0 || p.b.minCoeff() >= 0) {  // z = 0 is a solution
      r.status = SolveStatus::Converged;
      r.lambda = Eigen::VectorXd::Zero(n);
      r.sweeps = 0;
      cp.flush_final(r.lambda);
      finish(p, r);
      return r;
    }
    Eigen::VectorXd S(n);
    for (int i = 0; i < n; ++i) {
      const double d = p.A.coeff(i, i);
      S[i] = (d > 0 && std::isfinite(1.0 / std::sqrt(d))) ? 1.0 / std::sqrt(d) : 1.0;
    }
    const Eigen::MatrixXd M = S.asDiagonal() * Eigen::MatrixXd(p.A) * S.asDiagonal();
    const Eigen::VectorXd q = S.cwiseProduct(p.b);
    const double mmax = M.cwiseAbs().maxCoeff();
    const double mscale = (mmax > 0 && std::isfinite(mmax)) ? mmax : 1.0;
    const double qscale = q.cwiseAbs().maxCoeff();  // > 0 here (some q_i < 0)
    // Scaled problem: M' = M̃/mscale, q' = q̃/qscale, z = S z'·qscale/mscale.
    const int cols = 2 * n + 2, z0col = 2 * n, rhs = 2 * n + 1;
    using Tableau = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    Tableau T = Tableau::Zero(n, cols);  // row-major: pivots are row operations
    T.leftCols(n).setIdentity();
    T.middleCols(n, n) = -M / mscale;
    T.col(z0col).setConstant(-1.0);
    T.col(rhs) = q / qscale;
    std::vector<int> basis(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) basis[static_cast<size_t>(i)] = i;  // w_i basic

    auto pivot = [&](int row, int col) {
      const double piv = T(row, col);
      T.row(row) /= piv;
      for (int i = 0; i < n; ++i)
        if (const double f = T(i, col); i != row && f != 0.0) T.row(i) -= f * T.row(row);
      T.col(col).setZero();
      T(row, col) = 1.0;
      basis[static_cast<size_t>(row)] = col;
    };

    int first = 0;
    for (int i = 1; i < n; ++i)
      if (T(i, rhs) < T(first, rhs)) first = i;  // lowest index among ties
    int leaving = basis[static_cast<size_t>(first)];
    pivot(first, z0col);
    int pivots = 1;
    const int cap = 50 * n + 10;
    bool solved = false;
    std::string why;
    while (true) {
      if (pivots >= cap) {
        why = "pivot cap " + std::to_string(cap) + " reached";
        break;
      }
      const int entering = leaving < n ? leaving + n : leaving - n;  // complement
      const Eigen::VectorXd col = T.col(entering);
      const double tol = 1e-12 * std::max(1.0, col.cwiseAbs().maxCoeff());
      int best = -1;
      double best_ratio = kInf;
      for (int i = 0; i < n; ++i) {
        if (col[i] <= tol) continue;
        const double ratio = T(i, rhs) / col[i];
        if (best < 0 || ratio < best_ratio - 1e-12 * std::max(1.0, std::abs(best_ratio))) {
          best = i;
          best_ratio = ratio;
        } else if (ratio <= best_ratio + 1e-12 * std::max(1.0, std::abs(best_ratio))) {
          // Tie: z₀ leaves first; otherwise lexicographic minimum of B⁻¹ rows / col_i.
          const bool i_z0 = basis[static_cast<size_t>(i)] == z0col;
          const bool b_z0 = basis[static_cast<size_t>(best)] == z0col;
          if (b_z0) continue;
          if (i_z0) {
            best = i;
            best_ratio = std::min(best_ratio, ratio);
            continue;
          }
          for (int j = 0; j < n; ++j) {
            const double a = T(i, j) / col[i], b = T(best, j) / col[best];
            if (a < b - 1e-14) {
              best = i;
              best_ratio = std::min(best_ratio, ratio);
              break;
            }
            if (a > b + 1e-14) break;
          }
        }
      }
      if (best < 0) {
        r.status = SolveStatus::Infeasible;
        why = "ray termination after " + std::to_string(pivots) +
              " pivots: no solution found (for copositive-plus M, e.g. symmetric PSD, the LCP is infeasible)";
        break;
      }
      leaving = basis[static_cast<size_t>(best)];
      pivot(best, entering);
      ++pivots;
      if (!T.allFinite()) {
        why = "tableau became non-finite";
        break;
      }
      if (leaving == z0col) {
        solved = true;
        break;
      }
    }
    r.sweeps = pivots;
    if (!solved) {
      if (r.status != SolveStatus::Infeasible) r.status = SolveStatus::Failed;
      r.lambda = Eigen::VectorXd::Zero(n);
      r.message = "lemke: " + why;
      finish(p, r);
      return r;
    }
    // Read the solution, then refine on the active set S (the basic z's).
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    std::vector<int> act;  // the active set: indices of basic z's
    for (int i = 0; i < n; ++i) {
      const int v = basis[static_cast<size_t>(i)];
      if (v >= n && v < 2 * n) {
        z[v - n] = S[v - n] * std::max(0.0, T(i, rhs)) * qscale / mscale;
        act.push_back(v - n);
      }
    }
    double res = natural_residual(p, z);
    if (!act.empty()) {
      const int m = static_cast<int>(act.size());
      Eigen::MatrixXd Mss(m, m);
      Eigen::VectorXd qs(m);
      for (int a = 0; a < m; ++a) {
        qs[a] = -q[act[static_cast<size_t>(a)]] / qscale;
        for (int b = 0; b < m; ++b) Mss(a, b) = M(act[static_cast<size_t>(a)], act[static_cast<size_t>(b)]) / mscale;
      }
      const Eigen::PartialPivLU<Eigen::MatrixXd> lu(Mss);
      Eigen::VectorXd zs = lu.solve(qs);
      for (int step = 0; step < 2; ++step) zs += lu.solve(qs - Mss * zs);
      if (zs.allFinite()) {
        Eigen::VectorXd zr = Eigen::VectorXd::Zero(n);
        for (int a = 0; a < m; ++a) {
          const int j = act[static_cast<size_t>(a)];
          zr[j] = S[j] * std::max(0.0, zs[a]) * qscale / mscale;
        }
        const double rr = natural_residual(p, zr);
        if (rr < res) {
          res = rr;
          z = zr;
        }
      }
    }
    if (!(res <= target)) {
      SolverOptions po;
      po.exact_tolerance = o.exact_tolerance;
      po.record_theta = false;
      po.max_sweeps = 200;
      const SolveResult polished = make_newton()->solve(p, z, po);
      if (polished.residual < res) {
        res = polished.residual;
        z = polished.lambda;
        r.message = "lemke: refined by newton polish";
      }
    }
    r.lambda = z;
    r.status = res <= target ? SolveStatus::Converged : SolveStatus::Failed;
    if (r.status == SolveStatus::Failed)
      r.message = "lemke: complementarity error " + std::to_string(res) + " above tolerance " +
                  std::to_string(target) + " after refinement";
    if (r.status == SolveStatus::Converged) cp.flush_final(z);
    finish(p, r);
    return r;
  }
};

}  // namespace

std::unique_ptr<LcpSolver> make_lemke() { return std::make_unique<LemkeSolver>(); }

}  // namespace dc::solvers
