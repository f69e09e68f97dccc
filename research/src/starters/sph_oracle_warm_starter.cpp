// sph and sph-residual (oracles, sph_warm_starter.hpp): this step's λ* — or its correction
// λ* − builtin — splatted at the contact points and read back there through the SPH grid. The
// bound of what a grid-based predictor (the cnn; a residual cnn) can do with this transfer.
#include <string>
#include <utility>
#include <vector>

#include "dc/warmstart/sph_warm_starter.hpp"
#include "oracle_starters.hpp"

namespace dc {

namespace {

class SphOracleWarmStarter final : public WarmStarter {
 public:
  /// residual = false: sph (λ* itself); true: sph-residual (builtin + the correction's read-back).
  SphOracleWarmStarter(const SphTransferDef& def, std::string arg, bool residual)
      : transfer_(def), arg_(std::move(arg)), residual_(residual) {}
  std::string name() const override {
    const std::string base = residual_ ? "sph-residual" : "sph";
    return arg_.empty() ? base : base + ":" + arg_;
  }
  bool uses_oracle() const override { return true; }
  double oracle_ms() const override { return oracle_ms_; }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    oracle_ms_ = 0;
    points_.clear();
    for (const Contact& c : w.contacts()) points_.push_back(c.point);
    // builtin's rows: the base a residual grid is added to (unprojected, as the cnn's).
    Eigen::VectorXd base = Eigen::VectorXd::Zero(w.problem().rows());
    Eigen::VectorXd star = step_oracle(v, oracle_ms_);
    if (residual_) {
      put_previous_lambda_by_key(w, base);
      star -= base;  // the correction λ* − λ_builtin, per row
    }
    w.constraints().gather(star, values_);
    if (points_.empty()) return Eigen::VectorXd::Zero(w.problem().rows());
    SphTransfer& transfer = transfer_.on_box_of(w);
    transfer.splat(points_, values_);
    if (!residual_) return contact_values_to_rows(w, transfer.gather(transfer.grid(), points_));
    Eigen::VectorXd out = base + w.constraints().scatter(transfer.gather(transfer.grid(), points_));
    project_feasible(w.problem(), out);
    return out;
  }

 private:
  SceneSphTransfer transfer_;
  std::string arg_;
  bool residual_;
  double oracle_ms_ = 0;
  std::vector<Vec2> points_;
  std::vector<double> values_;
};

std::unique_ptr<WarmStarter> make(const WarmStartSpec& spec, bool residual) {
  return std::make_unique<SphOracleWarmStarter>(parse_sph_options(spec), spec.arg, residual);
}

}  // namespace

std::unique_ptr<WarmStarter> make_sph_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  return make(spec, false);
}

std::unique_ptr<WarmStarter> make_sph_residual_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  return make(spec, true);
}

}  // namespace dc
