#pragma once
// The SPH setting of a grid-based warm starter or feature image: kernel, node spacing d,
// support h and read-back normalisation, with the default the project measured best and the
// one parser of its command-line form "KERNEL:D:H[:NORMALISATION]" (e.g. `sph:spiky:0.25:0.25`,
// `sph-prev:poly6:0.5:0.5:legacy`, `generate --grid poly6:0.5:0.5`).
#include <string>

#include "dc/sph/sph_transfer.hpp"

namespace dc {

/// The setting the bench's `sph` uses by default (chosen by `deepcontact sph-study`, docs/sph.md):
/// poly6, d = 0.5, h = 0.355, Shepard read-back, on a W × H box, 2 channels.
SphTransferDef default_sph_setting(double width, double height);

/// Parses "KERNEL:D:H[:NORMALISATION]" onto `def` (empty text leaves it unchanged); ConfigError
/// "sph setting '…': …" naming the bad part otherwise.
void parse_sph_setting(const std::string& text, SphTransferDef& def);

}  // namespace dc
