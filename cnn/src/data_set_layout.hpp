#pragma once
// Private to the data-set writer and reader: the dataset paths, the root attributes, and
// reading the parameters back (docs/formats.md "Data set" is the public description).
#include <string>

#include "dc/cnn/data_set.hpp"
#include "dc/io/h5.hpp"

namespace dc::dataset {

// Commit order of one simulation: every row dataset, then kSimsRows, then kSimsSeed.
inline constexpr const char* kSimsSeed = "/sims/seed";  // int64 (S): the commit mark, written last
inline constexpr const char* kSimsBodies = "/sims/bodies";
inline constexpr const char* kSimsSamples = "/sims/samples";
inline constexpr const char* kSimsContacts = "/sims/contacts";
inline constexpr const char* kSimsResidual = "/sims/max_residual";

inline constexpr const char* kFeatures = "/samples/features";
inline constexpr const char* kLabels = "/samples/labels";

/// format_version of a sharded data set's manifest (data_set_shards.hpp); a single file,
/// and each shard, is kDataSetFormatVersion (1).
inline constexpr int kShardedFormatVersion = 2;

/// Samples per chunk of the image datasets (one 61 × 61 × 5 float32 feature row is 74 KB).
inline constexpr hsize_t kImageChunkRows = 4;
inline constexpr int kDeflate = 4;
/// Rows per chunk of the uncompressed per-sample index (8 KiB of int64) and of /sims: the
/// automatic ≈ 256 KiB chunks would make every one-simulation shard ≥ 3 MB of padding.
inline constexpr hsize_t kIndexChunkRows = 1024;
inline constexpr hsize_t kSimsChunkRows = 64;

/// Writes the root attributes of `p` (format, version, scene, grid, channels, oracle, ...).
void write_params(H5File& f, const DataSetParams& p);
/// Reads them back: IoError naming the file for a wrong format/version or a missing/bad attribute.
DataSetParams read_params(const H5File& f);
/// "" when the parameters that fix a data set's content are equal, else a phrase naming
/// the first one that differs, e.g. "--seed (file 1, requested 2)".
std::string first_difference(const DataSetParams& file, const DataSetParams& wanted);

/// Creates every (empty, extendible) dataset of the layout for `p`'s grid and channels.
void create_layout(H5File& f, const DataSetParams& p);

/// Row counts implied by the first `completed` simulations (read from /sims).
struct RowCounts {
  int completed = 0;
  std::int64_t samples = 0, body_rows = 0, contact_rows = 0;
};
/// Completed simulations = length of /sims/seed; the row counts they imply. IoError when
/// /sims is inconsistent (a /sims dataset shorter than /sims/seed, negative counts).
RowCounts committed_rows(const H5File& f);

/// Appends simulation `r` at row position `at` (advanced past it): every row dataset, then
/// /sims with /sims/seed last; /samples/sim holds `sim_id`. InvalidArgument for a record
/// whose arrays disagree in size. No flush.
void append_simulation(H5File& f, const SimulationRecord& r, int sim_id, RowCounts& at);

}  // namespace dc::dataset
