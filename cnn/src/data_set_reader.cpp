// DataSetReader: opens a data set, checks it against its own attributes, and loads
// samples. Only completed simulations (the rows of /sims/seed) are visible. A sharded data
// set's manifest (format_version 2) reads like a single file: its bulk datasets are virtual
// datasets over the shards, which are checked to be present first.
#include <algorithm>
#include <cstring>

#include "data_set_layout.hpp"
#include "data_set_shards.hpp"
#include "dc/cnn/data_set.hpp"
#include "dc/core/error.hpp"

namespace dc {

using namespace dataset;

namespace {

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t comma = std::min(s.find(',', start), s.size());
    out.push_back(s.substr(start, comma - start));
    start = comma + 1;
  }
  return out;
}

}  // namespace

DataSetReader::DataSetReader(const std::string& path) : file_(H5File::open_read(path)) {
  const H5File& f = file_;
  params_ = read_params(f);
  // A sharded data set's bulk datasets are virtual: a missing shard would read as fill values.
  if (f.attribute<std::int32_t>("/", "format_version") == kShardedFormatVersion) check_manifest_shards(f);
  feature_names_ = split_commas(f.attribute_string("/", "feature_channels"));
  label_names_ = split_commas(f.attribute_string("/", "label_channels"));
  nx_ = f.attribute<std::int32_t>("/", "grid_nx");
  ny_ = f.attribute<std::int32_t>("/", "grid_ny");

  const RowCounts rows = committed_rows(f);
  samples_ = rows.samples;
  const auto need = [&](const char* p, const H5Shape& row_shape, std::int64_t n) {
    if (!f.is_dataset(p)) throw IoError(path + ": " + p + ": missing (truncated or not a data set)");
    H5Shape expected = row_shape;
    expected.insert(expected.begin(), kH5Any);
    f.require_shape(p, expected);
    if (static_cast<std::int64_t>(f.rows(p)) < n)
      throw IoError(path + ": " + p + ": has " + std::to_string(f.rows(p)) + " rows, /sims records " +
                    std::to_string(n) + " (truncated data set)");
  };
  const auto cf = static_cast<hsize_t>(feature_names_.size()), lc = static_cast<hsize_t>(label_names_.size());
  const auto h = static_cast<hsize_t>(ny_), w = static_cast<hsize_t>(nx_);
  for (const char* p : {"/samples/sim", "/samples/step", "/samples/body_begin", "/samples/body_count",
                        "/samples/contact_begin", "/samples/contact_count", "/samples/residual"})
    need(p, {}, rows.samples);
  need(kFeatures, {cf, h, w}, rows.samples);
  need(kLabels, {lc, h, w}, rows.samples);
  for (const char* p : {"/bodies/position", "/bodies/velocity"}) need(p, {2}, rows.body_rows);
  for (const char* p : {"/bodies/omega", "/bodies/angle", "/bodies/radius", "/bodies/mass"}) need(p, {}, rows.body_rows);
  for (const char* p : {"/contacts/body_a", "/contacts/body_b", "/contacts/gap"}) need(p, {}, rows.contact_rows);
  for (const char* p : {"/contacts/point", "/contacts/normal", "/contacts/lambda_star"}) need(p, {2}, rows.contact_rows);

  const auto k = static_cast<hsize_t>(rows.completed);
  const auto n = static_cast<hsize_t>(rows.samples);
  if (k > 0) {
    const auto seed = f.read_rows<std::int64_t>(kSimsSeed, 0, k);
    const auto bodies = f.read_rows<std::int32_t>(kSimsBodies, 0, k);
    const auto samples = f.read_rows<std::int64_t>(kSimsSamples, 0, k);
    const auto contacts = f.read_rows<std::int64_t>(kSimsContacts, 0, k);
    const auto residual = f.read_rows<double>(kSimsResidual, 0, k);
    std::int64_t begin = 0;
    for (hsize_t i = 0; i < k; ++i) {
      sims_.push_back({static_cast<int>(i), static_cast<std::uint64_t>(seed[i]), bodies[i], begin, samples[i],
                       contacts[i], residual[i]});
      begin += samples[i];
    }
  }
  if (n > 0) {
    sample_sim_ = f.read_rows<std::int32_t>("/samples/sim", 0, n);
    sample_step_ = f.read_rows<std::int32_t>("/samples/step", 0, n);
    contact_count_ = f.read_rows<std::int32_t>("/samples/contact_count", 0, n);
    contact_begin_ = f.read_rows<std::int64_t>("/samples/contact_begin", 0, n);
  }
  // Cross-check the per-sample index against /sims, so a corrupt file fails here and not
  // later with out-of-range reads.
  for (const DataSetSimulation& s : sims_)
    for (std::int64_t r = s.sample_begin; r < s.sample_begin + s.samples; ++r) {
      const auto i = static_cast<std::size_t>(r);
      if (sample_sim_[i] != s.index || contact_begin_[i] < 0 || contact_count_[i] < 0 ||
          contact_begin_[i] + contact_count_[i] > rows.contact_rows)
        throw IoError(path + ": /samples: row " + std::to_string(r) + " disagrees with /sims (corrupt data set)");
    }
}

void DataSetReader::require_sample(std::int64_t sample) const {
  if (sample < 0 || sample >= samples_)
    throw InvalidArgument(path() + ": sample " + std::to_string(sample) + " out of range (the file has " +
                          std::to_string(samples_) + ")");
}

int DataSetReader::sample_simulation(std::int64_t sample) const {
  require_sample(sample);
  return sample_sim_[static_cast<std::size_t>(sample)];
}

int DataSetReader::sample_step(std::int64_t sample) const {
  require_sample(sample);
  return sample_step_[static_cast<std::size_t>(sample)];
}

std::vector<std::int64_t> DataSetReader::samples_of(std::span<const int> simulations) const {
  std::vector<std::int64_t> out;
  for (int s : simulations) {
    if (s < 0 || s >= static_cast<int>(sims_.size()))
      throw InvalidArgument(path() + ": simulation " + std::to_string(s) + " out of range (the file has " +
                            std::to_string(sims_.size()) + " completed)");
    const DataSetSimulation& sim = sims_[static_cast<std::size_t>(s)];
    for (std::int64_t r = 0; r < sim.samples; ++r) out.push_back(sim.sample_begin + r);
  }
  return out;
}

Tensor DataSetReader::read_images(const char* dataset, int channels, std::span<const std::int64_t> samples) const {
  for (std::int64_t s : samples) require_sample(s);
  Tensor out(static_cast<int>(samples.size()), channels, ny_, nx_);
  // Read runs of consecutive rows with one hyperslab each (chunks are decompressed once per run).
  std::size_t i = 0;
  while (i < samples.size()) {
    std::size_t j = i + 1;
    while (j < samples.size() && samples[j] == samples[j - 1] + 1) ++j;
    const auto rows = file_.read_rows<float>(dataset, static_cast<hsize_t>(samples[i]), j - i);
    std::memcpy(out.sample(static_cast<int>(i)), rows.data(), rows.size() * sizeof(float));
    i = j;
  }
  return out;
}

Tensor DataSetReader::features(std::span<const std::int64_t> samples) const {
  return read_images(kFeatures, feature_channels(), samples);
}

Tensor DataSetReader::labels(std::span<const std::int64_t> samples) const {
  return read_images(kLabels, label_channels(), samples);
}

std::vector<TrainingSample> DataSetReader::training_samples(std::span<const int> simulations) const {
  std::vector<TrainingSample> out;
  for (int s : simulations) {
    const int one[] = {s};
    for (TrainingSample& t : training_samples(samples_of(one), s)) out.push_back(std::move(t));
  }
  return out;
}

std::vector<TrainingSample> DataSetReader::training_samples(std::span<const std::int64_t> rows, int simulation) const {
  std::vector<TrainingSample> out;
  const Tensor f = features(rows), l = labels(rows);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    TrainingSample t;
    t.features = Tensor(1, f.c(), f.h(), f.w());
    t.labels = Tensor(1, l.c(), l.h(), l.w());
    std::memcpy(t.features.data(), f.sample(static_cast<int>(r)), f.shape().sample_count() * sizeof(float));
    std::memcpy(t.labels.data(), l.sample(static_cast<int>(r)), l.shape().sample_count() * sizeof(float));
    t.simulation = simulation;
    out.push_back(std::move(t));
  }
  return out;
}

SampleContacts DataSetReader::contacts(std::int64_t sample) const {
  require_sample(sample);
  const auto i = static_cast<std::size_t>(sample);
  const auto b = static_cast<hsize_t>(contact_begin_[i]), n = static_cast<hsize_t>(contact_count_[i]);
  SampleContacts c;
  if (n == 0) return c;
  c.body_a = file_.read_rows<std::int32_t>("/contacts/body_a", b, n);
  c.body_b = file_.read_rows<std::int32_t>("/contacts/body_b", b, n);
  c.gap = file_.read_rows<double>("/contacts/gap", b, n);
  const auto point = file_.read_rows<double>("/contacts/point", b, n);
  const auto normal = file_.read_rows<double>("/contacts/normal", b, n);
  const auto lambda = file_.read_rows<double>("/contacts/lambda_star", b, n);
  for (hsize_t k = 0; k < n; ++k) {
    c.point.push_back({point[2 * k], point[2 * k + 1]});
    c.normal.push_back({normal[2 * k], normal[2 * k + 1]});
    c.lambda_n.push_back(lambda[2 * k]);
    c.lambda_t.push_back(lambda[2 * k + 1]);
  }
  return c;
}

}  // namespace dc
