#pragma once
// The training data set of the CNN (docs/design.md §4–5; layout in docs/formats.md "Data
// set"): for every step with contacts of M seeded simulations, the feature image, the label
// image (oracle λ* → grid), and the raw body state and contacts (with λ*) behind them.
// SimulationGenerator (data_generator.cpp) runs simulation i → SimulationRecord;
// DataSetWriter (data_set_writer.cpp) appends records in simulation order; DataSetReader
// (data_set_reader.cpp) opens, validates and loads; generate_data_set
// (data_set_generation.hpp) runs the first two over a whole data set.
// DataSetWriter's single-file layout (format_version 1) appends in place, /sims/seed last as
// the commit mark: the completed simulations are the length of /sims/seed and extra rows of an
// interrupted append are ignored. It survives stops between appends, not a SIGKILL inside one
// (libhdf5 updates metadata in place), so `generate` writes shards instead.
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dc/cnn/feature_image.hpp"
#include "dc/core/vec2.hpp"
#include "dc/engine/world_def.hpp"
#include "dc/io/h5.hpp"
#include "dc/learning/tensor.hpp"
#include "dc/learning/trainer.hpp"

namespace dc {

inline constexpr const char* kDataSetFormat = "deepcontact-dataset";
inline constexpr int kDataSetFormatVersion = 1;

/// The method that computes λ* (stored as the root attribute `oracle_method`).
enum class OracleKind {
  /// Matrix-free PGS from the builtin warm start (previous step's λ by key) until θ ≤
  /// tolerance or `sweeps` sweeps. The default: within the data-generation budget
  /// (docs/design.md §6).
  Pgs,
  /// solve_oracle (minimum-map Newton, then a PGS polish when needed) from the builtin warm
  /// start — a smaller residual than Pgs at a cost beyond the data-generation budget
  /// (docs/design.md §6).
  Newton,
};
/// "pgs" / "newton".
const char* to_string(OracleKind kind);
/// Inverse of to_string; ConfigError "oracle method 'x': expected pgs or newton" otherwise.
OracleKind parse_oracle_kind(std::string_view text);

/// How λ* of each step is computed (stored as the root attributes oracle, oracle_method,
/// oracle_tolerance, oracle_sweeps).
struct DataSetOracle {
  OracleKind method = OracleKind::Pgs;
  /// pgs: stopping θ [N]; newton: accepted natural residual (relative to max(1, ‖λ‖∞)).
  double tolerance = 1e-9;
  int sweeps = 5000;  ///< pgs: sweep cap; newton: polish sweeps
  /// "pgs theta=1e-09 sweeps=5000 warmstart=builtin" — the attribute text (compared on resume).
  [[nodiscard]] std::string describe() const;
  /// ConfigError naming the field.
  void validate() const;
};

/// Everything that fixes the content of a data set; stored as root attributes and required
/// to be equal on resume. The number of simulations is not part of it (a resumed run may
/// ask for more).
struct DataSetParams {
  /// The base scene (with time.steps = the steps per simulation). Simulation i replaces
  /// bodies.seed by seed + i and bodies.count by its drawn count.
  WorldDef scene;
  FeatureImageDef image;
  DataSetOracle oracle;
  std::uint64_t seed = 1;  ///< S: simulation i uses scene seed S + i
  int count_min = 50;      ///< body count of simulation i: U{count_min … count_max} from Rng(S + i)
  int count_max = 100;
  /// ConfigError naming the field (counts, scene, image, oracle).
  void validate() const;
  /// The scene of simulation i (seed and count set).
  [[nodiscard]] WorldDef simulation_scene(int index) const;
};

/// One finished simulation, buffered in memory until it is its turn to be written.
/// Per-sample arrays have one entry per recorded step (a step with ≥ 1 contact).
struct SimulationRecord {
  int index = 0;             ///< simulation i (0-based)
  std::uint64_t seed = 0;    ///< scene seed S + i
  int bodies = 0;            ///< B: the body count (the final one when bodies enter during the run)
  /// Bodies of each sample when they vary (inflow, [[body]] spawn: inflow.hpp); empty = B each.
  std::vector<std::int32_t> body_count;
  double max_residual = 0;   ///< worst natural-map residual of λ* over its steps [N]
  std::vector<std::int32_t> step;           ///< step index (0-based) of each sample
  std::vector<std::int32_t> contact_count;  ///< C_s per sample
  std::vector<double> residual;             ///< natural-map residual of λ* per sample [N]
  std::vector<float> features;              ///< samples × Cf·ny·nx
  std::vector<float> labels;                ///< samples × 2·ny·nx
  // Body state before the step's solve, B rows per sample (sample-major).
  std::vector<double> position, velocity;   ///< (x, y) pairs [m], [m/s]
  std::vector<double> omega, angle;         ///< [rad/s], [rad]
  std::vector<double> radius, mass;         ///< [m], [kg]
  // The step's contacts, C_s rows per sample.
  std::vector<std::int32_t> body_a, body_b; ///< body indices; walls −1 left, −2 right, −3 bottom, −4 top
  std::vector<double> point, normal;        ///< (x, y) pairs [m], [1]
  std::vector<double> gap;                  ///< [m]
  std::vector<double> lambda_star;          ///< (λ_n, λ_t) pairs [N]
  [[nodiscard]] std::size_t samples() const { return step.size(); }
  [[nodiscard]] std::size_t contacts() const { return body_a.size(); }
};

/// Runs the simulations of a data set. Each simulation is a pure function of
/// (params, index): no shared state, so simulations can run on any threads in any order.
class SimulationGenerator {
 public:
  /// Validates `params` (ConfigError).
  explicit SimulationGenerator(DataSetParams params);
  [[nodiscard]] const DataSetParams& params() const { return params_; }
  /// Simulation `index`: steps the world with λ* and records every step with contacts.
  /// `keep_going` is polled before each step; when it returns false the simulation stops
  /// and std::nullopt is returned (nothing of it is kept). Throws on a non-finite λ*.
  [[nodiscard]] std::optional<SimulationRecord> run(int index, const std::function<bool()>& keep_going = {}) const;

 private:
  DataSetParams params_;
};

/// Writes a data set file simulation by simulation (one thread; records in index order).
class DataSetWriter {
 public:
  /// Creates `path` (truncating an existing file) with the empty layout and the attributes.
  static DataSetWriter create(const std::string& path, const DataSetParams& params);
  /// Opens an interrupted file for appending: checks format, version and that every
  /// parameter equals `params` (ConfigError naming the first differing one and the file),
  /// then cuts every dataset back to the rows of the completed simulations.
  static DataSetWriter resume(const std::string& path, const DataSetParams& params);

  DataSetWriter(DataSetWriter&&) noexcept = default;
  DataSetWriter& operator=(DataSetWriter&&) noexcept = default;

  [[nodiscard]] int completed_simulations() const { return completed_; }
  [[nodiscard]] std::int64_t samples() const { return samples_; }
  [[nodiscard]] const std::string& path() const { return file_.path(); }

  /// Appends one simulation (rows, then /sims with /sims/seed last) and flushes.
  /// InvalidArgument unless record.index == completed_simulations().
  void append(const SimulationRecord& record);
  /// Flushes and closes (errors are reported, unlike the destructor's close).
  void close();

 private:
  explicit DataSetWriter(H5File file);
  H5File file_;
  int completed_ = 0;
  std::int64_t samples_ = 0, body_rows_ = 0, contact_rows_ = 0;
};

/// One completed simulation of a data set file.
struct DataSetSimulation {
  int index = 0;
  std::uint64_t seed = 0;
  int bodies = 0;
  std::int64_t sample_begin = 0;  ///< first sample row
  std::int64_t samples = 0;
  std::int64_t contacts = 0;
  double max_residual = 0;
};

/// The contacts of one sample with their oracle forces (the λ-error reference).
struct SampleContacts {
  std::vector<std::int32_t> body_a, body_b;
  std::vector<Vec2> point, normal;
  std::vector<double> gap;
  std::vector<double> lambda_n, lambda_t;  ///< λ* [N]
};

/// Reads a data set file. Only the completed simulations (the length of /sims/seed) are
/// visible. Opening checks the format name, version, attributes and every dataset's shape
/// against each other; anything wrong or truncated is an IoError naming the file and object.
class DataSetReader {
 public:
  explicit DataSetReader(const std::string& path);

  [[nodiscard]] const std::string& path() const { return file_.path(); }
  [[nodiscard]] const DataSetParams& params() const { return params_; }
  [[nodiscard]] int nx() const { return nx_; }
  [[nodiscard]] int ny() const { return ny_; }
  [[nodiscard]] int feature_channels() const { return static_cast<int>(feature_names_.size()); }
  [[nodiscard]] int label_channels() const { return static_cast<int>(label_names_.size()); }
  [[nodiscard]] const std::vector<std::string>& feature_channel_names() const { return feature_names_; }
  [[nodiscard]] const std::vector<std::string>& label_channel_names() const { return label_names_; }

  [[nodiscard]] const std::vector<DataSetSimulation>& simulations() const { return sims_; }
  [[nodiscard]] std::int64_t samples() const { return samples_; }
  [[nodiscard]] int sample_simulation(std::int64_t sample) const;
  [[nodiscard]] int sample_step(std::int64_t sample) const;
  /// All sample rows of the listed simulations, in the order given.
  [[nodiscard]] std::vector<std::int64_t> samples_of(std::span<const int> simulations) const;

  /// [N, Cf, ny, nx] / [N, 2, ny, nx] for the listed sample rows (in that order).
  [[nodiscard]] Tensor features(std::span<const std::int64_t> samples) const;
  [[nodiscard]] Tensor labels(std::span<const std::int64_t> samples) const;
  /// Training examples (features, labels, simulation id) of the listed simulations.
  [[nodiscard]] std::vector<TrainingSample> training_samples(std::span<const int> simulations) const;
  /// Training examples of the listed sample rows (in that order), all marked as `simulation`.
  [[nodiscard]] std::vector<TrainingSample> training_samples(std::span<const std::int64_t> rows, int simulation) const;
  /// The contacts of one sample, with λ*.
  [[nodiscard]] SampleContacts contacts(std::int64_t sample) const;

 private:
  void require_sample(std::int64_t sample) const;
  Tensor read_images(const char* path, int channels, std::span<const std::int64_t> samples) const;

  H5File file_;
  DataSetParams params_;
  int nx_ = 0, ny_ = 0;
  std::vector<std::string> feature_names_, label_names_;
  std::vector<DataSetSimulation> sims_;
  std::int64_t samples_ = 0;
  std::vector<std::int32_t> sample_sim_, sample_step_, contact_count_;
  std::vector<std::int64_t> contact_begin_;
};

}  // namespace dc
