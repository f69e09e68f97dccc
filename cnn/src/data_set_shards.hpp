#pragma once
// Private to the data-set generation and reader: the sharded layout (format_version 2,
// docs/formats.md "Sharded layout"). OUT is the manifest (root attributes, /sims/*, the
// per-sample index with global row offsets, /shards/{file,bytes}, and the bulk datasets as HDF5
// virtual datasets over the shards, so any reader sees the single-file layout);
// OUT.shards/RUN/sim-NNNNNN.h5 is one simulation in the format_version 1 layout; OUT.partial
// ("deepcontact-generate run RUN") exists while a run is incomplete. Every file is written with
// write_file_atomically (tmp, fsync, rename, directory fsync), the manifest after all M shards:
// a kill leaves committed shards intact and at most one `.tmp` per worker, which resume discards.
#include <string>
#include <vector>

#include "data_set_layout.hpp"
#include "dc/cnn/data_set.hpp"

namespace dc::dataset {

/// OUT.shards (the folder of every run's shard folder).
std::string shard_root(const std::string& out);
/// OUT.shards/RUN.
std::string shard_dir(const std::string& out, const std::string& run);
/// "sim-000012.h5".
std::string shard_file_name(int index);
/// A fresh run id: 16 hex digits from the clock, the pid and std::random_device.
std::string new_run_id();

/// Writes OUT.partial naming `run` (atomically).
void write_run_marker(const std::string& out, const std::string& run);
/// The run named by OUT.partial. ConfigError when OUT.partial is an interrupted single-file
/// data set of an older build, or not a marker at all.
std::string read_run_marker(const std::string& out);

/// Writes simulation `rec` as the shard dir/sim-NNNNNN.h5 (complete or absent).
void write_shard(const std::string& dir, const DataSetParams& params, const SimulationRecord& rec);

/// The shards of a run folder: committed (final names, sorted indices) and incomplete
/// (`*.tmp` of an interrupted write, full paths).
struct ShardScan {
  std::vector<int> committed;
  std::vector<std::string> incomplete;
};
ShardScan scan_shards(const std::string& dir);

/// IoError/ConfigError unless the shard of `index` in `dir` was written with `params`.
void check_shard_params(const std::string& dir, int index, const DataSetParams& params);

/// Writes the manifest OUT over shards 0..M-1 of `run` (all must exist and carry `params`;
/// each is opened and checked). Atomic. Returns the data set's sample count.
std::int64_t write_manifest(const std::string& out, const std::string& run, const DataSetParams& params, int simulations);

/// True when the manifest OUT lists shards of `run` (false for any file that is not such a manifest).
bool manifest_names_run(const std::string& out, const std::string& run);

/// For the reader of a manifest: IoError naming the first listed shard that is missing or
/// has another size than the manifest recorded (a virtual dataset would read fill values).
void check_manifest_shards(const H5File& manifest);

}  // namespace dc::dataset
