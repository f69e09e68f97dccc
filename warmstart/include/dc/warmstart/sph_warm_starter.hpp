#pragma once
// Grid-based warm starters built on the SPH transfer (docs/design.md §4):
//   sph       this step's λ* → grid (kernel W, spacing d, support h) → back at the contact
//             points: the best any grid-based predictor (the CNN) can do; uses the oracle.
//   sph-prev  the previous step's solved λ at the previous contact points → grid → this
//             step's contact points: a non-oracle grid starter (the "SPH of the past").
//   sph-residual  builtin + the grid read-back of this step's correction λ* − λ_builtin
//             (splatted at the contact points): the best a *residual* grid predictor (a
//             residual cnn model, λ⁰ = λ_prev + read-back) can do with this transfer; an
//             oracle. Unlike sph it keeps builtin's exact per-contact detail and loses only
//             the correction's sub-grid part.
//   sph-gain, sph-gain-add  builtin × (1 + a grid GAIN field of the correction) (+ the
//             remainder's additive read-back): the bound of a multiplicative grid correction,
//             which leaves the per-contact detail to λ_prev (sph_gain_warm_starter.cpp); oracles.
// Options: `sph:KERNEL:D:H[:NORMALISATION]`, e.g. `sph:spiky:0.25:0.25`, `sph:poly6:0.5:0.5:legacy`.
#include <string>

#include "dc/warmstart/sph_transfer.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

/// The setting the bench's `sph` uses by default (chosen by `deepcontact sph-study`).
SphTransferDef default_sph_setting(double width, double height);

/// Parses "KERNEL:D:H[:NORMALISATION]" onto `def` (empty text leaves it unchanged).
void parse_sph_setting(const std::string& text, SphTransferDef& def);

/// Channels (λ_n, λ_t) of the contacts of `world` at their points, particle-major.
void contact_lambda_channels(const std::vector<Contact>& contacts, std::vector<Vec2>& points,
                             std::vector<double>& values);

}  // namespace dc
