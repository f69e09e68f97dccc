#pragma once
// Model files (HDF5, via dc::H5File), format version 2: root attributes format =
// "deepcontact-cnn-model", format_version, input_shape, output_shape; /arch (the ArchSpec TOML
// text); /weights/<node>/<param> (float32, the parameter tensor's shape);
// /normalisation/{input,output}_{mean,std}; /grid attributes d, h, kernel, nx, ny, label_kind,
// label_scale, correction_deadzone; /grid/feature_channels, /grid/label_channels. Version-1
// files (without the three label attributes) load as absolute models. Field types and units:
// docs/learning.md "Model files". load_model parses the stored names into a typed ModelGrid
// and rejects an unknown kernel, feature channel or label kind (IoError). save_model writes
// "<path>.tmp" and renames it onto <path> when complete.
#include <filesystem>
#include <functional>

#include "dc/io/h5.hpp"
#include "dc/learning/model.hpp"

namespace dc {

inline constexpr int kModelFormatVersion = 2;
/// The oldest format version load_model still reads.
inline constexpr int kModelFormatVersionOldest = 1;

/// Throws IoError (one line) if the file cannot be written.
void save_model(Model& model, const std::filesystem::path& path);

/// save_model, with `extra(file)` called before the atomic rename so that additional
/// objects (e.g. `/training` provenance, or a checkpoint's `/train_state`) land in the same
/// atomic write. load_model ignores objects it does not know.
void save_model(Model& model, const std::filesystem::path& path, const std::function<void(H5File&)>& extra);

/// Throws IoError with a one-line message for a missing, non-HDF5 or truncated file, a
/// different format version, a missing dataset or attribute, a weight of the wrong shape,
/// or an arch text that does not parse/build.
Model load_model(const std::filesystem::path& path);

}  // namespace dc
