#include "dc/warmstart/sph_warm_starter.hpp"

#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>

#include "dc/engine/error.hpp"
#include "dc/warmstart/oracle.hpp"
#include "starters.hpp"

namespace dc {

SphTransferDef default_sph_setting(double width, double height) {
  SphTransferDef d;
  d.grid.width = width;
  d.grid.height = height;
  d.grid.spacing = 0.5;
  d.grid.channels = 2;
  // The best setting of `deepcontact sph-study --seeds 1..2` (docs/sph.md): poly6 with
  // h = 0.71·d, the smallest support that still reaches a node from every point of a cell
  // (h ≥ d·√2/2), so neighbouring contacts overlap least and the Shepard round trip is exact.
  d.kernel = SphKernelType::Poly6;
  d.support = 0.355;
  d.normalisation = SphNormalisation::Shepard;
  return d;
}

void parse_sph_setting(const std::string& text, SphTransferDef& def) {
  if (text.empty()) return;
  std::vector<std::string> parts;
  std::stringstream ss(text);
  for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
  if (parts.size() < 3 || parts.size() > 4)
    throw ConfigError("sph setting '" + text + "': expected KERNEL:D:H[:NORMALISATION]");
  def.kernel = parse_sph_kernel(parts[0]);
  auto number = [&](const std::string& s, const char* what) {
    try {
      std::size_t used = 0;
      const double v = std::stod(s, &used);
      if (used == s.size() && v > 0 && std::isfinite(v)) return v;
    } catch (const std::exception&) {
    }
    throw ConfigError("sph setting '" + text + "': " + what + " must be a number > 0");
  };
  def.grid.spacing = number(parts[1], "D");
  def.support = number(parts[2], "H");
  if (parts.size() == 4) def.normalisation = parse_sph_normalisation(parts[3]);
  try {
    def.validate();
  } catch (const std::exception& e) {
    throw ConfigError("sph setting '" + text + "': " + e.what());
  }
}

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

namespace {

/// Writes per-contact (λ_n, λ_t) read back from the grid into the row vector.
Eigen::VectorXd to_rows(const World& w, std::span<const double> v) {
  Eigen::VectorXd out = w.constraints().scatter(v);
  project_feasible(w.problem(), out);
  return out;
}

/// What is splatted on the grid (see the file comment of sph_warm_starter.hpp).
enum class SphSource { Oracle, Previous, Residual };

class SphWarmStarter final : public WarmStarter {
 public:
  SphWarmStarter(const SphTransferDef& def, std::string arg, SphSource source)
      : def_(def), arg_(std::move(arg)), source_(source) {}
  std::string name() const override {
    const std::string base = source_ == SphSource::Previous ? "sph-prev"
                             : source_ == SphSource::Residual ? "sph-residual"
                                                              : "sph";
    return arg_.empty() ? base : base + ":" + arg_;
  }
  bool uses_oracle() const override { return source_ != SphSource::Previous; }
  double oracle_ms() const override { return oracle_ms_; }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    oracle_ms_ = 0;
    targets_.clear();
    for (const Contact& c : w.contacts()) targets_.push_back(c.point);
    // builtin's rows: the base a residual grid is added to (unprojected, as the cnn's).
    Eigen::VectorXd base = Eigen::VectorXd::Zero(w.problem().rows());
    if (source_ == SphSource::Previous) {
      contact_lambda_channels(w.previous_contacts(), points_, values_);
    } else {
      Eigen::VectorXd star = step_oracle(v, oracle_ms_);
      points_ = targets_;
      if (source_ == SphSource::Residual) {
        put_previous_lambda_by_key(w, base);
        star -= base;  // the correction λ* − λ_builtin, per row
      }
      w.constraints().gather(star, values_);
    }
    if (targets_.empty()) return Eigen::VectorXd::Zero(w.problem().rows());
    if (points_.empty()) return Eigen::VectorXd::Zero(w.problem().rows());
    // The grid covers the scene's box: (re)build the transfer when the box changes.
    if (!transfer_ || transfer_->def().grid.width != w.def().world.width ||
        transfer_->def().grid.height != w.def().world.height) {
      SphTransferDef d = def_;
      d.grid.width = w.def().world.width;
      d.grid.height = w.def().world.height;
      transfer_.emplace(d);
    }
    transfer_->splat(points_, values_);
    if (source_ != SphSource::Residual) return to_rows(w, transfer_->gather(transfer_->grid(), targets_));
    Eigen::VectorXd out = base + w.constraints().scatter(transfer_->gather(transfer_->grid(), targets_));
    project_feasible(w.problem(), out);
    return out;
  }

 private:
  SphTransferDef def_;
  std::optional<SphTransfer> transfer_;
  std::string arg_;
  SphSource source_;
  double oracle_ms_ = 0;
  std::vector<Vec2> points_, targets_;
  std::vector<double> values_;
};

}  // namespace

std::unique_ptr<WarmStarter> make_sph_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  SphTransferDef def = default_sph_setting(30.0, 30.0);  // box replaced by the scene's
  parse_sph_setting(spec.arg, def);
  return std::make_unique<SphWarmStarter>(def, spec.arg, SphSource::Oracle);
}

std::unique_ptr<WarmStarter> make_sph_prev_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  SphTransferDef def = default_sph_setting(30.0, 30.0);
  parse_sph_setting(spec.arg, def);
  return std::make_unique<SphWarmStarter>(def, spec.arg, SphSource::Previous);
}

std::unique_ptr<WarmStarter> make_sph_residual_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  SphTransferDef def = default_sph_setting(30.0, 30.0);
  parse_sph_setting(spec.arg, def);
  return std::make_unique<SphWarmStarter>(def, spec.arg, SphSource::Residual);
}

}  // namespace dc
