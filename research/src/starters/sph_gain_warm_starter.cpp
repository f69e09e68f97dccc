// sph-gain / sph-gain-add: oracle bounds of a multiplicative grid correction of builtin.
// An additive grid correction loses the correction's sub-grid detail (force chains), which is
// already in λ_prev; a gain field λ⁰ = λ_prev·(1 + g(p)) keeps it. Per row kind r ∈ {n, t}:
//     N_r(x) = Σ_c W(|x − p_c|) δ_c,r λp_c,r        D_r(x) = Σ_c W(|x − p_c|) λp_c,r²
//     ĝ_r(p) = bilinear(N_r)(p) / bilinear(D_r)(p)  (0 where bilinear(D_r)(p) = 0)
// the kernel-weighted least-squares gain, exact for an isolated contact (ĝ = δ/λp). Contacts
// with λp = 0 get no gain; sph-gain-add adds the Shepard read-back of the remainder δ − ĝ·λp.
// Both use this step's λ*.
#include <chrono>
#include <optional>

#include "dc/sph/sph_splat.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/sph_warm_starter.hpp"
#include "oracle_starters.hpp"

namespace dc {

namespace {

class SphGainWarmStarter final : public WarmStarter {
 public:
  SphGainWarmStarter(const SphTransferDef& def, std::string arg, bool additive)
      : def_(def), arg_(std::move(arg)), additive_(additive) {}
  std::string name() const override {
    const std::string base = additive_ ? "sph-gain-add" : "sph-gain";
    return arg_.empty() ? base : base + ":" + arg_;
  }
  bool uses_oracle() const override { return true; }
  double oracle_ms() const override { return oracle_ms_; }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    oracle_ms_ = 0;
    const int rows = w.problem().rows();
    Eigen::VectorXd base = Eigen::VectorXd::Zero(rows);
    if (w.contacts().empty()) return base;
    const Eigen::VectorXd star = step_oracle(v, oracle_ms_);
    put_previous_lambda_by_key(w, base);  // λ_prev by key, unprojected (as the cnn's base)
    const ContactConstraints& cons = w.constraints();
    const std::size_t n = w.contacts().size();
    ensure_grids(w);

    // Splat (δ_n λp_n, δ_t λp_t, λp_n², λp_t²) and read the four fields back bilinearly.
    points_.clear();
    values_.assign(4 * n, 0.0);
    for (std::size_t c = 0; c < n; ++c) {
      const int k = static_cast<int>(c);
      points_.push_back(w.contacts()[c].point);
      const double pn = cons.lambda_n(base, k), pt = cons.lambda_t(base, k);
      values_[4 * c + 0] = (cons.lambda_n(star, k) - pn) * pn;
      values_[4 * c + 1] = (cons.lambda_t(star, k) - pt) * pt;
      values_[4 * c + 2] = pn * pn;
      values_[4 * c + 3] = pt * pt;
    }
    splat_to_grid(kernel_->kernel(), points_, values_, *fields_, nullptr);
    back_.resize(4 * n);
    gather_bilinear(*fields_, points_, back_);

    // λ⁰ = λ_prev (1 + ĝ); the remainder δ − ĝ λ_prev for sph-gain-add.
    Eigen::VectorXd out = base;
    remainder_.assign(2 * n, 0.0);
    for (std::size_t c = 0; c < n; ++c) {
      const int k = static_cast<int>(c);
      const auto [gn, gt] = read_gains(back_, c);
      const double pn = cons.lambda_n(base, k), pt = cons.lambda_t(base, k);
      const double ln = pn * (1 + gn), lt = pt * (1 + gt);
      cons.put(k, ln, lt, out);
      remainder_[2 * c + 0] = cons.lambda_n(star, k) - ln;
      remainder_[2 * c + 1] = cons.lambda_t(star, k) - lt;
    }
    if (additive_) {
      const std::span<const double> r = kernel_->round_trip(points_, remainder_);
      out += cons.scatter(r);
    }
    project_feasible(w.problem(), out);
    return out;
  }

 private:
  // The grids cover the scene's box: (re)built when the box changes.
  void ensure_grids(const World& w) {
    if (kernel_ && kernel_->def().grid.width == w.def().world.width &&
        kernel_->def().grid.height == w.def().world.height)
      return;
    SphTransferDef d = def_;
    d.grid.width = w.def().world.width;
    d.grid.height = w.def().world.height;
    d.grid.channels = 2;
    d.normalisation = SphNormalisation::Shepard;  // the remainder's read-back
    kernel_.emplace(d);
    SphGridDef g = d.grid;
    g.channels = 4;
    fields_.emplace(g);
  }

  SphTransferDef def_;
  std::string arg_;
  bool additive_;
  double oracle_ms_ = 0;
  std::optional<SphTransfer> kernel_;  // kernel, geometry and the remainder's Shepard round trip
  std::optional<SphGrid> fields_;      // N_n, N_t, D_n, D_t
  std::vector<Vec2> points_;
  std::vector<double> values_, back_, remainder_;
};

std::unique_ptr<WarmStarter> make(const WarmStartSpec& spec, bool additive) {
  return std::make_unique<SphGainWarmStarter>(parse_sph_options(spec), spec.arg, additive);
}

}  // namespace

std::unique_ptr<WarmStarter> make_sph_gain_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  return make(spec, false);
}

std::unique_ptr<WarmStarter> make_sph_gain_add_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  return make(spec, true);
}

}  // namespace dc
