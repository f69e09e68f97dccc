// "pgs": matrix-free projected Gauss–Seidel on body velocities (the engine default, the
// Box2D form of the seed's iteration). A = J M⁻¹ Jᵀ Δt is never formed; the solver keeps
//
//     Δu = M⁻¹ Jᵀ λ Δt          (3 entries per body: Δv_x, Δv_y [m/s], Δω [rad/s])
//
// so that the row residual is r_i = A_i·λ + b_i = J_i·Δu + b_i, and after a row update
// λ_i ← λ_i + δ it restores the invariant with Δu += (M⁻¹ J_iᵀ Δt) δ. Each contact row
// touches at most two bodies, so one row costs 6 multiply-adds for r_i, a clamp and 6 for
// the update. The "prepare" stage packs every row into a compact struct (two body offsets,
// the 6 coefficients of J_i/A_ii, the 6 of M⁻¹J_iᵀΔt, b_i/A_ii, bounds) so the sweep is a tight
// scalar loop over contiguous memory. Rows touching one body (wall contacts) point their
// second body at a dummy zero body at the end of Δu, which keeps the loop branch-free.
//
// It produces the iterates of pgs-assembled up to round-off (A_ii and r_i are summed in a
// different order); tests/engine/solver_pgs_test.cpp checks that.
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc::solvers {
namespace {

struct PackedRow {
  std::array<double, 6> j;   // J_i / A_ii on (body a: v_x, v_y, ω, body b: v_x, v_y, ω)
  std::array<double, 6> mj;  // M⁻¹ J_iᵀ Δt on the same 6 entries [(m/s)/(N)]
  double b;                  // b_i / A_ii [N]
  bool singular;             // A_ii ≤ 0: j and b are unscaled, see singular_row_update
  double lo_fixed, hi_fixed; // fixed bounds (0, 0 for friction rows)
  double mu;                 // μ for friction rows, 0 otherwise
  int a, bb;                 // offsets of the bodies in Δu (3·body); bb may be the dummy body
  int coupled;               // normal row of a friction row, the row itself otherwise
};

/// Packs J, M⁻¹, Δt into rows. Returns an error message when a row of J touches more than
/// two bodies (the matrix-free form assumes pairwise contacts).
std::string pack_rows(const LcpProblem& p, std::vector<PackedRow>& rows, std::vector<int>& singular,
                      int& dummy_offset) {
  const int n = p.rows();
  const int bodies = static_cast<int>(p.J.cols() / 3) + (p.J.cols() % 3 != 0 ? 1 : 0);
  dummy_offset = 3 * bodies;
  const RowBounds bounds(p);
  rows.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    PackedRow& r = rows[static_cast<size_t>(i)];
    r.j.fill(0.0);
    r.mj.fill(0.0);
    r.a = r.bb = -1;
    for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) {
      const int col = static_cast<int>(it.col());
      const int body_off = 3 * (col / 3), comp = col % 3;
      int slot;
      if (r.a < 0 || r.a == body_off) {
        r.a = body_off;
        slot = comp;
      } else if (r.bb < 0 || r.bb == body_off) {
        r.bb = body_off;
        slot = 3 + comp;
      } else {
        return "row " + std::to_string(i) + " of J touches more than two bodies";
      }
      r.j[static_cast<size_t>(slot)] += it.value();
    }
    double diag = 0.0;
    for (int s = 0; s < 6; ++s) {
      const int off = s < 3 ? r.a : r.bb;
      if (off < 0) continue;
      const double im = p.inv_mass[off + s % 3];
      r.mj[static_cast<size_t>(s)] = r.j[static_cast<size_t>(s)] * im * p.dt;
      diag += r.j[static_cast<size_t>(s)] * r.mj[static_cast<size_t>(s)];
    }
    if (r.a < 0) r.a = dummy_offset;
    if (r.bb < 0) r.bb = dummy_offset;
    // Pre-scale J_i and b_i by 1/A_ii: the step r_i/A_ii then costs no multiply on the
    // row-to-row dependency chain (same iterate as pgs-assembled up to round-off).
    const double inv = 1.0 / diag;
    r.singular = !(diag > 0 && std::isfinite(inv));
    const double scale = r.singular ? 1.0 : inv;
    if (r.singular) singular.push_back(i);
    for (double& v : r.j) v *= scale;
    const auto u = static_cast<size_t>(i);
    r.b = p.b[i] * scale;
    r.lo_fixed = bounds.lo_fixed[u];
    r.hi_fixed = bounds.hi_fixed[u];
    r.mu = bounds.mu[u];
    r.coupled = bounds.coupled[u];
  }
  return {};
}

class PgsMatrixFreeSolver final : public LcpSolver {
 public:
  [[nodiscard]] std::string name() const override { return "pgs"; }
  [[nodiscard]] bool needs_jacobian() const override { return true; }
  [[nodiscard]] SolveResult solve(const LcpProblem& p, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& o) const override {
    if (!p.has_jacobian()) {
      // A problem from a file has only A: run the same iteration in its assembled form.
      SolveResult r = solve_assembled_gauss_seidel(p, lambda0, o, 1.0, name());
      if (r.status != SolveStatus::InvalidInput)
        r.message = "no Jacobian in the problem: ran the assembled form of PGS" +
                    (r.message.empty() ? std::string() : "; " + r.message);
      return r;
    }
    Eigen::VectorXd lambda;
    if (auto bad = check_input(p, lambda0, name(), lambda)) return *bad;

    std::vector<PackedRow> rows;
    std::vector<int> singular;
    int dummy = 0;
    if (std::string err = pack_rows(p, rows, singular, dummy); !err.empty()) {
      SolveResult r;
      r.status = SolveStatus::InvalidInput;
      r.lambda = lambda;
      r.message = "pgs: " + err + "; use pgs-assembled";
      finish(p, r);
      return r;
    }
    // Δu = M⁻¹ Jᵀ λ⁰ Δt, plus the dummy body (always zero: its coefficients are zero).
    std::vector<double> du(static_cast<size_t>(dummy + 3), 0.0);
    {
      const Eigen::VectorXd jt = p.J.transpose() * lambda;
      for (int c = 0; c < jt.size(); ++c) du[static_cast<size_t>(c)] = p.inv_mass[c] * jt[c] * p.dt;
    }
    const int n = p.rows();
    SolveResult r = run_sweeps(p, std::move(lambda), o, [&](Eigen::VectorXd& l, bool& nonfinite) {
      double* __restrict lam = l.data();
      double* __restrict u = du.data();
      const PackedRow* __restrict row = rows.data();
      double theta = 0.0;
      bool bad = false;
      for (int i = 0; i < n; ++i, ++row) {
        double* ua = u + row->a;
        double* ub = u + row->bb;
        // Pairwise (tree) sum: the row-to-row dependency chain through Δu is the cost of
        // Gauss–Seidel, and a left-to-right sum of 7 terms would put 6 serial adds on it.
        const double s0 = row->j[0] * ua[0] + row->j[1] * ua[1];
        const double s1 = row->j[2] * ua[2] + row->j[3] * ub[0];
        const double s2 = row->j[4] * ub[1] + row->j[5] * ub[2];
        const double res = (row->b + s0) + (s1 + s2);
        const double old = lam[i];
        const double t = row->mu * std::max(0.0, lam[row->coupled]);
        const double lo = row->lo_fixed - t, hi = row->hi_fixed + t;
        double x = !row->singular ? old - res : singular_row_update(old, res, lo, hi);
        x = std::min(std::max(x, lo), hi);
        const double d = x - old;
        bad |= !std::isfinite(x);
        lam[i] = x;
        ua[0] += row->mj[0] * d;
        ua[1] += row->mj[1] * d;
        ua[2] += row->mj[2] * d;
        ub[0] += row->mj[3] * d;
        ub[1] += row->mj[4] * d;
        ub[2] += row->mj[5] * d;
        theta = std::max(theta, std::abs(d));
      }
      // A body velocity that overflowed would make later residuals meaningless even
      // while λ stays finite (clamped); treat it as divergence.
      u[dummy] = u[dummy + 1] = u[dummy + 2] = 0.0;
      if (!std::isfinite(theta) || !Eigen::Map<const Eigen::VectorXd>(u, dummy).allFinite()) bad = true;
      nonfinite = nonfinite || bad;
      return theta;
    });
    report_singular_rows(p, singular, r);
    finish(p, r);
    return r;
  }
};

}  // namespace

std::unique_ptr<LcpSolver> make_pgs_matrix_free() { return std::make_unique<PgsMatrixFreeSolver>(); }

}  // namespace dc::solvers
