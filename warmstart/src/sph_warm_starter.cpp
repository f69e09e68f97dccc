#include "dc/warmstart/sph_warm_starter.hpp"

#include <cmath>
#include <optional>
#include <sstream>

#include "dc/core/error.hpp"
#include "starters.hpp"

namespace dc {

void contact_lambda_channels(const std::vector<Contact>& contacts, std::vector<Vec2>& points,
                             std::vector<double>& values) {
  points.clear();
  values.clear();
  for (const Contact& c : contacts) {
    points.push_back(c.point);
    values.push_back(c.lambda_n);
    values.push_back(c.lambda_t);
  }
}

SphTransfer& SceneSphTransfer::on_box_of(const World& w) {
  if (!transfer_ || transfer_->def().grid.width != w.def().world.width ||
      transfer_->def().grid.height != w.def().world.height) {
    SphTransferDef d = def_;
    d.grid.width = w.def().world.width;
    d.grid.height = w.def().world.height;
    transfer_.emplace(d);
  }
  return *transfer_;
}

Eigen::VectorXd contact_values_to_rows(const World& w, std::span<const double> per_contact) {
  Eigen::VectorXd out = w.constraints().scatter(per_contact);
  project_feasible(w.problem(), out);
  return out;
}

namespace {

/// sph-prev: the previous step's solved λ at the previous contact points → grid → this step's
/// contact points (see sph_warm_starter.hpp). No oracle.
class SphPrevWarmStarter final : public WarmStarter {
 public:
  SphPrevWarmStarter(const SphTransferDef& def, std::string arg) : transfer_(def), arg_(std::move(arg)) {}
  std::string name() const override { return arg_.empty() ? "sph-prev" : "sph-prev:" + arg_; }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    targets_.clear();
    for (const Contact& c : w.contacts()) targets_.push_back(c.point);
    contact_lambda_channels(w.previous_contacts(), points_, values_);
    if (targets_.empty() || points_.empty()) return Eigen::VectorXd::Zero(w.problem().rows());
    SphTransfer& transfer = transfer_.on_box_of(w);
    transfer.splat(points_, values_);
    return contact_values_to_rows(w, transfer.gather(transfer.grid(), targets_));
  }

 private:
  SceneSphTransfer transfer_;
  std::string arg_;
  std::vector<Vec2> points_, targets_;
  std::vector<double> values_;
};

}  // namespace

std::unique_ptr<WarmStarter> make_sph_prev_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  return std::make_unique<SphPrevWarmStarter>(parse_sph_options(spec), spec.arg);
}

}  // namespace dc
