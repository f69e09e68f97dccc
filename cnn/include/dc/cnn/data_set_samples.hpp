#pragma once
// The training examples of a data set read from disk on demand (`deepcontact train`,
// docs/learning.md "Training", docs/robustness.md "Memory of train"): a SampleSource that
// holds only the index of the selected rows (a few bytes per sample), and reads features and
// labels when the Trainer asks — runs of consecutive rows with one HDF5 read each, checksums
// verified by the HDF5 layer as for every read. Works the same on a single file and on a
// sharded data set's manifest (its datasets are virtual datasets over the shards).
#include <cstdint>
#include <vector>

#include "dc/cnn/data_set.hpp"
#include "dc/cnn/training_data.hpp"
#include "dc/learning/sample_source.hpp"

namespace dc {

/// The samples TrainingSampleDef selects from every completed simulation of a data set
/// (every `every`-th from `first_step`, in data order), their targets (training_labels) and
/// loss weights (1 + W·[contact_density > 0], one channel, when contact_weight W > 0).
/// Sample i of this source is load_training_samples(data, def)[i], value for value.
class DataSetSamples final : public SampleSource {
 public:
  /// Checks `def` against the data set (ConfigError naming the option and the file, as
  /// load_training_samples). `data` must outlive the source.
  DataSetSamples(const DataSetReader& data, TrainingSampleDef def);

  [[nodiscard]] std::size_t size() const override { return rows_.size(); }
  [[nodiscard]] int simulation(std::size_t i) const override { return simulation_[i]; }
  [[nodiscard]] Shape feature_shape() const override;
  [[nodiscard]] Shape label_shape() const override;
  [[nodiscard]] int weight_channels() const override { return def_.contact_weight > 0 ? 1 : 0; }
  void read(std::span<const std::size_t> indices, Tensor& x, Tensor& y, Tensor& w) const override;

  /// The data-set row of sample i.
  [[nodiscard]] std::int64_t row(std::size_t i) const { return rows_[i]; }

 private:
  const DataSetReader& data_;
  TrainingSampleDef def_;
  int density_ = -1;  // index of the contact_density channel, −1: none
  std::vector<std::int64_t> rows_;
  std::vector<int> simulation_;
};

}  // namespace dc
