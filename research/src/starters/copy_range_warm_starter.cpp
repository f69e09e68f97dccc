// copy-range: a diagnostic oracle — builtin plus only the part of the correction δ = λ* − λ_b
// the LCP velocity sees (docs/bench.md "Non-learned baselines"). A pile is statically
// indeterminate, so A = J M⁻¹ Jᵀ Δt has a null space in which a change of λ only redistributes
// forces. With δ = δ_⊥ + δ_0, δ_⊥ ∈ range(A):
//     λ⁰ = project(λ_b + δ_⊥),   δ_⊥ = V_r V_rᵀ δ
// V_r the eigenvectors of A whose eigenvalue exceeds 10⁻⁸ of the largest. Unprojected, λ⁰ has
// exactly λ*'s velocities; it lacks the redistribution δ_0 that puts λ* in its bounds
// (docs/research.md "Where PGS's sweeps go"). A dense eigendecomposition, O(rows³): refused
// above kMaxDenseDiagnosticRows rows (starters.hpp).
#include <Eigen/Eigenvalues>
#include <string>

#include "oracle_starters.hpp"

namespace dc {

namespace {

class CopyRangeWarmStarter final : public WarmStarter {
 public:
  std::string name() const override { return "copy-range"; }
  bool uses_oracle() const override { return true; }
  double oracle_ms() const override { return oracle_ms_; }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    const LcpProblem& p = w.problem();
    Eigen::VectorXd base = builtin_guess(w);
    oracle_ms_ = 0;
    if (w.contacts().empty()) return base;
    require_dense_diagnostic_size(p, "copy-range");
    const Eigen::VectorXd star = step_oracle(v, oracle_ms_);
    Eigen::VectorXd out = base + range_part(p, star - base);
    project_feasible(p, out);
    return out;
  }

 private:
  /// V_r V_rᵀ δ: δ's component in range(A).
  static Eigen::VectorXd range_part(const LcpProblem& p, const Eigen::VectorXd& delta) {
    const Eigen::MatrixXd J(p.J);
    const Eigen::MatrixXd A = J * (p.inv_mass * p.dt).asDiagonal() * J.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
    const Eigen::VectorXd& ev = es.eigenvalues();
    const double cut = 1e-8 * ev.maxCoeff();
    Eigen::VectorXd c = es.eigenvectors().transpose() * delta;
    for (int i = 0; i < c.size(); ++i)
      if (!(ev[i] > cut)) c[i] = 0;
    return es.eigenvectors() * c;
  }

  double oracle_ms_ = 0;
};

}  // namespace

std::unique_ptr<WarmStarter> make_copy_range_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  reject_argument(spec);
  return std::make_unique<CopyRangeWarmStarter>();
}

}  // namespace dc
