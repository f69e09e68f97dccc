#pragma once
// Model files (HDF5, via dc::H5File). Layout, format version 2 (version 1 files, which lack
// /grid label_kind, still load as "absolute" models):
//
//   /                      attrs  format = "deepcontact-cnn-model", format_version = 2 (int32),
//                                 input_shape = [C_in, ny, nx], output_shape = [C_out, ny, nx] (int32)
//   /arch                  string dataset: the ArchSpec TOML text (arch.hpp)
//   /weights/<node>/<p>    float32, shape of the parameter tensor: conv weight [Cout, Cin, k, k],
//                          conv bias [1, Cout, 1, 1], dense weight [O, D, 1, 1], bias [1, O, 1, 1]
//   /normalisation/{input_mean,input_std,output_mean,output_std}   float32 [C]
//   /grid                  group attrs d, h (float64), kernel (string), nx, ny (int32),
//                          label_kind (string, "absolute" | "residual"), label_scale (float64,
//                          asinh compression of the labels, 0 = none), correction_deadzone
//                          (float64 [N], residual models' soft threshold) — version ≥ 2;
//   /grid/feature_channels, /grid/label_channels   1-D string datasets
//
// In memory the grid is typed (ModelGrid: FeatureImageDef, LabelDef); load_model parses the
// stored names and rejects an unknown kernel, feature channel or label kind (IoError).
//
// save_model writes "<path>.tmp" and renames it onto <path> when complete.
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
