// builtin-coarse: builtin plus a Galerkin coarse-grid correction of its load — the coarse
// half of a two-grid cycle, computed from the LCP itself (docs/bench.md "Non-learned
// baselines"). Why: Gauss–Seidel removes contact-to-contact error quickly but an error smooth
// over the pile only by diffusion; the coarse space is a gain field on a grid of spacing D:
//     λ(g) = λ_b + P g,   (P g)_i = s_i · Σ_nodes β_i,node g_kind(i),node
// s_i = λ_b,i on the rows that carry load in λ_b (λ_n > 0; friction rows strictly inside the
// cone with λ_t ≠ 0; else 0), β the bilinear weights, kind ∈ {normal, friction}. Minimising
// E(λ) = ½ λᵀAλ + bᵀλ over the coarse space gives (Pᵀ A P) g = −Pᵀ (A λ_b + b), solved by ITER
// CG iterations from g = 0 (PSD; unreached nodes stay 0) with A x = J (Δt M⁻¹ (Jᵀ x)) applied
// matrix-free. λ⁰ = λ_b + P g projected into the bounds; unloaded (new) contacts keep 0.
#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "dc/sph/sph_grid.hpp"
#include "dc/warmstart/active_set_solve.hpp"
#include "starters.hpp"

namespace dc {

namespace {

class CoarseWarmStarter final : public WarmStarter {
 public:
  CoarseWarmStarter(CoarseStarterOptions s, std::string arg) : s_(s), arg_(std::move(arg)) {}
  std::string name() const override { return arg_.empty() ? "builtin-coarse" : "builtin-coarse:" + arg_; }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    Eigen::VectorXd base = builtin_guess(w);
    const LcpProblem& p = w.problem();
    if (w.contacts().empty() || !p.has_jacobian()) return base;
    build_basis(w, base);
    if (rows_.empty()) return base;

    // CG on (Pᵀ A P) g = −Pᵀ (A λ_b + b).
    const std::size_t n = 2 * nodes_;
    std::vector<double> g(n, 0.0), r(n), d(n), q(n);
    const Eigen::VectorXd w0 = lcp_velocity(p, base);
    restrict_rows(w0, r);
    for (double& x : r) x = -x;
    d = r;
    double rr = dot(r, r);
    const double rr0 = rr;
    for (int it = 0; it < s_.iterations && rr > 1e-28 * rr0 && rr > 0; ++it) {
      apply_galerkin(p, d, q);
      const double dq = dot(d, q);
      if (!(dq > 0)) break;  // a direction of zero energy: nothing more to gain
      const double alpha = rr / dq;
      for (std::size_t i = 0; i < n; ++i) {
        g[i] += alpha * d[i];
        r[i] -= alpha * q[i];
      }
      const double rr1 = dot(r, r);
      const double beta = rr1 / rr;
      rr = rr1;
      for (std::size_t i = 0; i < n; ++i) d[i] = r[i] + beta * d[i];
    }
    prolong(g, x_);
    Eigen::VectorXd out = base + x_;
    project_feasible(p, out);
    return out;
  }

 private:
  /// One loaded row: λ_i += s_i Σ_k β_k g[node_k] (channel offset included in node_k).
  struct Row {
    int row;
    double s;
    int node[4];
    double beta[4];
  };

  static double dot(const std::vector<double>& a, const std::vector<double>& b) {
    double t = 0;
    for (std::size_t i = 0; i < a.size(); ++i) t += a[i] * b[i];
    return t;
  }

  void build_basis(const World& w, const Eigen::VectorXd& base) {
    if (!grid_ || grid_->def().width != w.def().world.width || grid_->def().height != w.def().world.height)
      grid_.emplace(SphGridDef{w.def().world.width, w.def().world.height, s_.spacing, 1});
    nodes_ = grid_->nodes();
    rows_count_ = w.problem().rows();
    const int nx = grid_->nx();
    rows_.clear();
    const ContactConstraints& cons = w.constraints();
    for (std::size_t c = 0; c < w.contacts().size(); ++c) {
      const int k = static_cast<int>(c);
      const ContactConstraint& kc = cons[k];
      const ContactMode mode = contact_mode(cons, k, base);
      if (mode == ContactMode::Separating) continue;  // no load: the gain cannot move it
      const double ln = base[kc.normal_row];
      const BilinearStencil st = grid_->stencil(w.contacts()[c].point);
      const int idx[4] = {st.j0 * nx + st.i0, st.j0 * nx + st.i1, st.j1 * nx + st.i0, st.j1 * nx + st.i1};
      const double beta[4] = {st.w00(), st.w01(), st.w10(), st.w11()};
      auto add = [&](int row, double s, std::size_t offset) {
        Row r{row, s, {}, {}};
        for (int m = 0; m < 4; ++m) {
          r.node[m] = static_cast<int>(offset) + idx[m];
          r.beta[m] = beta[m];
        }
        rows_.push_back(r);
      };
      add(kc.normal_row, ln, 0);
      if (kc.has_friction() && mode == ContactMode::Sticking && base[kc.tangent_row] != 0)
        add(kc.tangent_row, base[kc.tangent_row], nodes_);
    }
  }

  /// x = P g (x sized to the problem's rows: zero outside the loaded rows).
  void prolong(const std::vector<double>& g, Eigen::VectorXd& x) const {
    x.setZero(rows_count_);
    for (const Row& r : rows_) {
      double v = 0;
      for (int m = 0; m < 4; ++m) v += r.beta[m] * g[static_cast<std::size_t>(r.node[m])];
      x[r.row] = r.s * v;
    }
  }

  /// out = Pᵀ y.
  void restrict_rows(const Eigen::VectorXd& y, std::vector<double>& out) const {
    std::fill(out.begin(), out.end(), 0.0);
    for (const Row& r : rows_) {
      const double v = r.s * y[r.row];
      for (int m = 0; m < 4; ++m) out[static_cast<std::size_t>(r.node[m])] += r.beta[m] * v;
    }
  }

  /// q = Pᵀ A P d, A applied matrix-free.
  void apply_galerkin(const LcpProblem& p, const std::vector<double>& d, std::vector<double>& q) {
    prolong(d, x_);
    y_ = lcp_apply(p, x_);
    restrict_rows(y_, q);
  }

  CoarseStarterOptions s_;
  std::string arg_;
  std::optional<SphGrid> grid_;  // geometry only (stencils)
  std::size_t nodes_ = 0;
  int rows_count_ = 0;  // the problem's rows (the size of P g)
  std::vector<Row> rows_;
  Eigen::VectorXd x_, y_;
};

}  // namespace

std::unique_ptr<WarmStarter> make_coarse_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  return std::make_unique<CoarseWarmStarter>(parse_coarse_options(spec), spec.arg);
}

}  // namespace dc
