// The sharded data-set layout: shards, the run marker, the manifest (data_set_shards.hpp).
#include "data_set_shards.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "data_set_layout.hpp"
#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"

namespace dc::dataset {
namespace {

namespace fs = std::filesystem;

constexpr const char* kMarkerPrefix = "deepcontact-generate run ";

/// The bulk datasets, which the manifest maps onto the shards (row shape given the grid).
struct BulkDataset {
  const char* path;
  H5Type type;
};
constexpr BulkDataset kBulk[] = {
    {kFeatures, H5Type::Float32},          {kLabels, H5Type::Float32},
    {"/bodies/position", H5Type::Float64}, {"/bodies/velocity", H5Type::Float64},
    {"/bodies/omega", H5Type::Float64},    {"/bodies/angle", H5Type::Float64},
    {"/bodies/radius", H5Type::Float64},   {"/bodies/mass", H5Type::Float64},
    {"/contacts/body_a", H5Type::Int32},   {"/contacts/body_b", H5Type::Int32},
    {"/contacts/point", H5Type::Float64},  {"/contacts/normal", H5Type::Float64},
    {"/contacts/gap", H5Type::Float64},    {"/contacts/lambda_star", H5Type::Float64},
};

/// Everything of the shards that the manifest holds as real data, concatenated.
struct ManifestIndex {
  std::vector<std::int64_t> seed, sims_samples, sims_contacts, body_begin, contact_begin, shard_bytes;
  std::vector<std::int32_t> sims_bodies, sample_sim, step, body_count, contact_count;
  std::vector<double> max_residual, residual;
  std::vector<std::string> files;
  std::vector<std::vector<H5VirtualSource>> bulk = std::vector<std::vector<H5VirtualSource>>(std::size(kBulk));
  std::vector<H5Shape> row_shape = std::vector<H5Shape>(std::size(kBulk));
  std::int64_t body_rows = 0, contact_rows = 0;
};

template <class T>
void append(std::vector<T>& to, const std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

/// Adds shard `index` (file `rel` relative to OUT's folder, opened as `f`) to the index.
void add_shard(ManifestIndex& m, const H5File& f, const std::string& rel, int index) {
  const RowCounts rows = committed_rows(f);
  if (rows.completed != 1) throw IoError(f.path() + ": a shard must hold exactly one simulation");
  const auto n = static_cast<hsize_t>(rows.samples);
  append(m.seed, f.read_rows<std::int64_t>(kSimsSeed, 0, 1));
  append(m.sims_bodies, f.read_rows<std::int32_t>(kSimsBodies, 0, 1));
  append(m.sims_samples, f.read_rows<std::int64_t>(kSimsSamples, 0, 1));
  append(m.sims_contacts, f.read_rows<std::int64_t>(kSimsContacts, 0, 1));
  append(m.max_residual, f.read_rows<double>(kSimsResidual, 0, 1));
  append(m.step, f.read_rows<std::int32_t>("/samples/step", 0, n));
  append(m.residual, f.read_rows<double>("/samples/residual", 0, n));
  for (const std::int64_t b : f.read_rows<std::int64_t>("/samples/body_begin", 0, n)) m.body_begin.push_back(m.body_rows + b);
  for (const std::int64_t c : f.read_rows<std::int64_t>("/samples/contact_begin", 0, n))
    m.contact_begin.push_back(m.contact_rows + c);
  append(m.body_count, f.read_rows<std::int32_t>("/samples/body_count", 0, n));
  append(m.contact_count, f.read_rows<std::int32_t>("/samples/contact_count", 0, n));
  m.sample_sim.insert(m.sample_sim.end(), n, index);
  for (std::size_t k = 0; k < std::size(kBulk); ++k) {
    const hsize_t used = k < 2 ? n : kBulk[k].path[1] == 'b' ? static_cast<hsize_t>(rows.body_rows)
                                                              : static_cast<hsize_t>(rows.contact_rows);
    H5Shape shape = f.shape(kBulk[k].path);
    if (shape.empty() || shape[0] != used)
      throw IoError(f.path() + ": " + kBulk[k].path + ": " + std::to_string(shape.empty() ? 0 : shape[0]) +
                    " rows, its /sims row says " + std::to_string(used) + " (damaged shard)");
    m.row_shape[k] = H5Shape(shape.begin() + 1, shape.end());
    m.bulk[k].push_back({rel, kBulk[k].path, used});
  }
  m.body_rows += rows.body_rows;
  m.contact_rows += rows.contact_rows;
  m.files.push_back(rel);
}

template <class T>
void write_rows(H5File& out, const char* path, const std::vector<T>& v) {
  out.write<T>(path, v, {static_cast<hsize_t>(v.size())});
}

void write_index(H5File& out, const ManifestIndex& m) {
  write_rows(out, kSimsSeed, m.seed);
  write_rows(out, kSimsBodies, m.sims_bodies);
  write_rows(out, kSimsSamples, m.sims_samples);
  write_rows(out, kSimsContacts, m.sims_contacts);
  write_rows(out, kSimsResidual, m.max_residual);
  write_rows(out, "/samples/sim", m.sample_sim);
  write_rows(out, "/samples/step", m.step);
  write_rows(out, "/samples/body_begin", m.body_begin);
  write_rows(out, "/samples/body_count", m.body_count);
  write_rows(out, "/samples/contact_begin", m.contact_begin);
  write_rows(out, "/samples/contact_count", m.contact_count);
  write_rows(out, "/samples/residual", m.residual);
  out.write_strings("/shards/file", m.files);
  write_rows(out, "/shards/bytes", m.shard_bytes);
}

void write_bulk(H5File& out, const ManifestIndex& m) {
  for (std::size_t k = 0; k < std::size(kBulk); ++k) {
    switch (kBulk[k].type) {
      case H5Type::Float32: out.create_virtual<float>(kBulk[k].path, m.row_shape[k], m.bulk[k]); break;
      case H5Type::Float64: out.create_virtual<double>(kBulk[k].path, m.row_shape[k], m.bulk[k]); break;
      case H5Type::Int32: out.create_virtual<std::int32_t>(kBulk[k].path, m.row_shape[k], m.bulk[k]); break;
      default: throw InvalidArgument("data set manifest: unexpected bulk type");
    }
  }
}

}  // namespace

std::string shard_root(const std::string& out) { return out + ".shards"; }

std::string shard_dir(const std::string& out, const std::string& run) { return shard_root(out) + "/" + run; }

std::string shard_file_name(int index) {
  char name[32];
  std::snprintf(name, sizeof name, "sim-%06d.h5", index);
  return name;
}

std::string new_run_id() {
  std::random_device device;
  const auto now = static_cast<std::uint64_t>(std::chrono::system_clock::now().time_since_epoch().count());
  const std::uint64_t id = now ^ (static_cast<std::uint64_t>(::getpid()) << 40) ^
                           (static_cast<std::uint64_t>(device()) << 20) ^ device();
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(id));
  return text;
}

void write_run_marker(const std::string& out, const std::string& run) {
  write_file_atomically(out + ".partial", std::string(kMarkerPrefix) + run + "\n");
}

std::string read_run_marker(const std::string& out) {
  const std::string marker = out + ".partial";
  std::ifstream in(marker, std::ios::binary);
  std::string line;
  std::getline(in, line);
  const std::string prefix = kMarkerPrefix;
  const std::string run = line.rfind(prefix, 0) == 0 ? line.substr(prefix.size()) : std::string();
  if (run.size() != 16 || run.find_first_not_of("0123456789abcdef") != std::string::npos) {
    if (line.rfind("\x89HDF", 0) == 0)
      throw ConfigError(marker + " is an interrupted data set of an older build (single-file layout): finish it "
                                 "with that build, or delete it and generate again");
    throw ConfigError(marker + ": not a generate run marker (expected '" + prefix + "<16 hex digits>')");
  }
  return run;
}

void write_shard(const std::string& dir, const DataSetParams& params, const SimulationRecord& rec) {
  AtomicH5File out(dir + "/" + shard_file_name(rec.index));
  H5File& f = out.file();
  write_params(f, params);
  f.set_attribute<std::int32_t>("/", "shard_simulation", rec.index);
  create_layout(f, params);
  RowCounts at;
  append_simulation(f, rec, 0, at);
  out.commit();
}

ShardScan scan_shards(const std::string& dir) {
  ShardScan scan;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    int index = -1;
    char tail[8] = {};
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0) {
      scan.incomplete.push_back(entry.path().string());
    } else if (std::sscanf(name.c_str(), "sim-%d.%7s", &index, tail) == 2 && std::string(tail) == "h5" &&
               index >= 0 && name == shard_file_name(index)) {
      scan.committed.push_back(index);
    }
  }
  if (ec) throw IoError(dir + ": cannot list the shards: " + ec.message());
  std::sort(scan.committed.begin(), scan.committed.end());
  return scan;
}

void check_shard_params(const std::string& dir, int index, const DataSetParams& params) {
  const H5File f = H5File::open_read(dir + "/" + shard_file_name(index));
  if (const std::string diff = first_difference(read_params(f), params); !diff.empty())
    throw ConfigError(f.path() + ": cannot resume: " + diff + " differs from the interrupted run");
}

std::int64_t write_manifest(const std::string& out, const std::string& run, const DataSetParams& params, int simulations) {
  const fs::path out_path(out);
  const std::string rel_dir = out_path.filename().string() + ".shards/" + run + "/";
  const std::string dir = shard_dir(out, run);
  ManifestIndex m;
  for (int i = 0; i < simulations; ++i) {
    const std::string file = dir + "/" + shard_file_name(i);
    const H5File f = H5File::open_read(file);
    if (const std::string diff = first_difference(read_params(f), params); !diff.empty())
      throw IoError(file + ": " + diff + " differs from the rest of the data set (a shard of another run)");
    add_shard(m, f, rel_dir + shard_file_name(i), i);
    m.shard_bytes.push_back(static_cast<std::int64_t>(fs::file_size(file)));
  }
  AtomicH5File manifest(out);
  manifest.add_whole_file_hash();  // its virtual datasets' mappings have no HDF5 checksum
  H5File& f = manifest.file();
  write_params(f, params);
  f.set_attribute<std::int32_t>("/", "format_version", kShardedFormatVersion);
  f.set_attribute("/", "layout", "shards");
  write_index(f, m);
  write_bulk(f, m);
  manifest.commit();
  return static_cast<std::int64_t>(m.step.size());
}

bool manifest_names_run(const std::string& out, const std::string& run) {
  try {
    const H5File f = H5File::open_read(out);
    if (!f.is_dataset("/shards/file")) return false;
    const std::vector<std::string> files = f.read_strings("/shards/file");
    return !files.empty() && files.front().find(".shards/" + run + "/") != std::string::npos;
  } catch (const std::exception&) {
    return false;
  }
}

void check_manifest_shards(const H5File& manifest) {
  if (!manifest.is_dataset("/shards/file") || !manifest.is_dataset("/shards/bytes"))
    throw IoError(manifest.path() + ": /shards: missing (not a complete data set manifest)");
  const std::vector<std::string> files = manifest.read_strings("/shards/file");
  const std::vector<std::int64_t> bytes = manifest.read<std::int64_t>("/shards/bytes");
  if (files.size() != bytes.size())
    throw IoError(manifest.path() + ": /shards/file and /shards/bytes differ in length (damaged manifest)");
  const fs::path folder = fs::path(manifest.path()).parent_path();
  for (std::size_t i = 0; i < files.size(); ++i) {
    const fs::path shard = folder / files[i];
    std::error_code ec;
    const auto size = fs::file_size(shard, ec);
    if (ec) throw IoError(manifest.path() + ": shard " + shard.string() + " is missing (" + ec.message() + ")");
    if (static_cast<std::int64_t>(size) != bytes[i])
      throw IoError(manifest.path() + ": shard " + shard.string() + " has " + std::to_string(size) +
                    " bytes, the manifest recorded " + std::to_string(bytes[i]) + " (replaced or damaged)");
  }
}

}  // namespace dc::dataset
