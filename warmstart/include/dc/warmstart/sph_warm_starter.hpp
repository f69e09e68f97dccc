#pragma once
// Grid-based warm starters built on the SPH transfer (docs/design.md §4, docs/bench.md):
//   sph           this step's λ* → grid → back at the contact points: the bound of any grid
//                 predictor (the CNN); an oracle.
//   sph-prev      the previous step's solved λ at its contact points → grid → this step's
//                 contact points; not an oracle.
//   sph-residual  builtin + the read-back of the splatted correction λ* − λ_builtin: the bound
//                 of a residual grid predictor; an oracle.
//   sph-gain, sph-gain-add  builtin × (1 + a grid gain field of the correction) (+ the
//                 remainder's additive read-back): the bound of a multiplicative grid
//                 correction (sph_gain_warm_starter.cpp); oracles.
// Options: `sph:KERNEL:D:H[:NORMALISATION]`, e.g. `sph:spiky:0.25:0.25`, `sph:poly6:0.5:0.5:legacy`.
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "dc/sph/sph_setting.hpp"
#include "dc/sph/sph_transfer.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

/// The SPH transfer of a grid-based starter, kept on the scene's box: the grid covers the
/// world's box, so the transfer is rebuilt from `def` (box replaced) whenever the box changes.
class SceneSphTransfer {
 public:
  explicit SceneSphTransfer(SphTransferDef def) : def_(std::move(def)) {}
  /// The transfer on w's box [0, W] × [0, H].
  SphTransfer& on_box_of(const World& w);

 private:
  SphTransferDef def_;
  std::optional<SphTransfer> transfer_;
};

/// Per-contact (λ_n, λ_t) pairs → the problem's rows, projected into the bounds (a grid
/// read-back is a valid PGS start whatever it returns).
Eigen::VectorXd contact_values_to_rows(const World& w, std::span<const double> per_contact);

/// Channels (λ_n, λ_t) of the contacts of `world` at their points, particle-major.
void contact_lambda_channels(const std::vector<Contact>& contacts, std::vector<Vec2>& points,
                             std::vector<double>& values);

}  // namespace dc
