// train_checkpoint.hpp + training_data.hpp: the checkpoint's /train_state round-trips, a
// checkpoint of another run is refused naming the option, and the samples of a data set
// carry the label definition's targets.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cnn/small_data_set.hpp"
#include "dc/cnn/data_set_generation.hpp"
#include "dc/cnn/data_set_samples.hpp"
#include "dc/cnn/train_checkpoint.hpp"
#include "dc/cnn/training_data.hpp"
#include "dc/core/error.hpp"
#include "dc/learning/arch.hpp"
#include "dc/learning/model_file.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

/// One small residual-capable data set for every test of this file.
class TrainCheckpoint : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("dc_train_checkpoint_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    DataSetGenerationDef d;
    d.params = test::small_data_set_params(12, 40, 11, 10, 14);
    d.params.image.channels = residual_feature_channels();
    d.out = (dir_ / "data.h5").string();
    d.simulations = 2;
    d.threads = 1;
    generate_data_set(d);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string data() { return (dir_ / "data.h5").string(); }
  static inline fs::path dir_;
};

TEST_F(TrainCheckpoint, StateRoundTripsAndAnotherRunIsRefused) {
  const DataSetReader r(data());
  TrainingSampleDef s;
  s.labels.kind = LabelKind::Residual;
  const ArchSpec arch = default_arch(2, 0.0);
  const TrainDef t;
  const RunIdentity id = training_run_identity(r, arch.to_toml(), t, s);
  ASSERT_FALSE(id.empty());
  EXPECT_EQ(id.front().first, "data_simulations");
  EXPECT_EQ(id.front().second, "2");

  Model model(arch, model_grid_for(r, s.labels), r.feature_channels());
  TrainState st;
  st.epochs_done = 2;
  st.rng_type = "mt19937";
  st.rng_state = {1, 2, 3, 250};
  st.validation_simulations = {1};
  st.velocity = {{0.5f, -1.0f}, {2.0f}};
  for (int e = 0; e < 2; ++e) st.history.push_back({e, 1.0 / (e + 1), NAN, 0.01, 0.3 * e});
  const fs::path ckpt = dir_ / "m.ckpt";
  save_checkpoint(model, ckpt, st, id);

  const TrainState back = read_train_state(H5File::open_read(ckpt.string()), id);
  EXPECT_EQ(back.epochs_done, 2);
  EXPECT_EQ(back.rng_type, st.rng_type);
  EXPECT_EQ(back.rng_state, st.rng_state);
  EXPECT_EQ(back.validation_simulations, st.validation_simulations);
  EXPECT_EQ(back.velocity, st.velocity);
  ASSERT_EQ(back.history.size(), 2u);
  EXPECT_EQ(back.history[1].epoch, 1);
  EXPECT_EQ(back.history[1].train_loss, 0.5);
  EXPECT_TRUE(std::isnan(back.history[1].validation_loss));
  EXPECT_EQ(back.history[1].seconds, 0.3);

  // Another option value: ConfigError naming the key, on one line.
  TrainDef other = t;
  other.learning_rate *= 2;
  try {
    (void)read_train_state(H5File::open_read(ckpt.string()), training_run_identity(r, arch.to_toml(), other, s));
    ADD_FAILURE() << "no ConfigError";
  } catch (const ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("lr"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  // Another shuffle buffer visits a large split in another order: refused as well.
  other = t;
  other.shuffle_buffer = 7;
  try {
    (void)read_train_state(H5File::open_read(ckpt.string()), training_run_identity(r, arch.to_toml(), other, s));
    ADD_FAILURE() << "no ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("shuffle_buffer"), std::string::npos) << e.what();
  }
  // A model file without state is not a checkpoint.
  save_model(model, dir_ / "plain.h5");
  EXPECT_THROW((void)read_train_state(H5File::open_read((dir_ / "plain.h5").string()), id), IoError);

  // The reloaded checkpoint resumes this run, not one with other labels or architecture.
  Model loaded = load_model(ckpt);
  EXPECT_NO_THROW(check_resumable(loaded, model_grid_for(r, s.labels), arch, ckpt.string(), data()));
  EXPECT_THROW(check_resumable(loaded, model_grid_for(r, LabelDef{}), arch, ckpt.string(), data()), ConfigError);
  EXPECT_THROW(check_resumable(loaded, model_grid_for(r, s.labels), default_arch(2, 0.3), ckpt.string(), data()),
               ConfigError);
}

TEST_F(TrainCheckpoint, SamplesCarryTheLabelDefinitionsTargets) {
  const DataSetReader r(data());
  TrainingSampleDef abs;
  abs.every = 3;
  abs.contact_weight = 4;
  const auto a = load_training_samples(r, abs);
  TrainingSampleDef res = abs;
  res.labels = {LabelKind::Residual, 2.0, 0.0};
  const auto b = load_training_samples(r, res);
  ASSERT_EQ(a.size(), b.size());
  std::size_t expected = 0;
  for (const DataSetSimulation& sim : r.simulations()) expected += static_cast<std::size_t>((sim.samples + 2) / 3);
  EXPECT_EQ(a.size(), expected);
  const auto& ch = r.params().image.channels;
  for (std::size_t k = 0; k < a.size(); ++k) {
    Tensor want = a[k].labels;
    training_labels(want, a[k].features, ch, res.labels);
    for (std::size_t i = 0; i < want.size(); ++i) ASSERT_EQ(b[k].labels[i], want[i]) << k << " " << i;
    // Weights 1 + W where the contact density is positive, 1 elsewhere.
    const std::size_t P = a[k].features.shape().plane();
    const float* cd = a[k].features.data() + 4 * P;  // contact_density is channel 4
    for (std::size_t p = 0; p < P; ++p) ASSERT_EQ(a[k].weights[p], cd[p] > 0 ? 5.0f : 1.0f);
  }
  TrainingSampleDef bad = abs;
  bad.labels.deadzone = 1.0;  // dead zone on an absolute model
  EXPECT_THROW((void)load_training_samples(r, bad), ConfigError);
  bad = abs;
  bad.every = 0;
  EXPECT_THROW((void)load_training_samples(r, bad), ConfigError);
}

// The on-demand source of `train` reads the sharded data set in any order and any grouping
// (one read may span both shards) with the values of the in-memory samples, and selects the
// same rows.
TEST_F(TrainCheckpoint, DataSetSamplesReadAnyOrderAcrossShardsLikeTheLoadedSamples) {
  const DataSetReader r(data());
  TrainingSampleDef def;
  def.every = 2;
  def.contact_weight = 3;
  def.labels = {LabelKind::Residual, 2.0, 0.0};
  const auto all = load_training_samples(r, def);
  const DataSetSamples source(r, def);
  ASSERT_EQ(source.size(), all.size());
  EXPECT_EQ(source.weight_channels(), 1);
  EXPECT_EQ(source.feature_shape(), all[0].features.shape());
  EXPECT_EQ(source.label_shape(), all[0].labels.shape());
  ASSERT_EQ(r.simulations().size(), 2u);
  for (std::size_t i = 0; i < source.size(); ++i) {
    EXPECT_EQ(source.simulation(i), all[i].simulation);
    EXPECT_EQ(r.sample_simulation(source.row(i)), source.simulation(i));
  }
  EXPECT_EQ(source.row(1) - source.row(0), 2);
  // Reversed order, blocks of 5 (the middle ones hold samples of both simulations).
  std::vector<std::size_t> order(source.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = order.size() - 1 - i;
  Tensor x, y, w;
  for (std::size_t first = 0; first < order.size(); first += 5) {
    const std::size_t b = std::min<std::size_t>(5, order.size() - first);
    source.read(std::span<const std::size_t>(order).subspan(first, b), x, y, w);
    for (std::size_t k = 0; k < b; ++k) {
      const TrainingSample& want = all[order[first + k]];
      const int j = static_cast<int>(k);
      ASSERT_EQ(std::memcmp(x.sample(j), want.features.data(), want.features.size() * sizeof(float)), 0);
      ASSERT_EQ(std::memcmp(y.sample(j), want.labels.data(), want.labels.size() * sizeof(float)), 0);
      ASSERT_EQ(std::memcmp(w.sample(j), want.weights.data(), want.weights.size() * sizeof(float)), 0);
    }
  }
}

// --first-step K keeps only samples of steps >= K, every K-th counted from the first kept.
TEST_F(TrainCheckpoint, FirstStepKeepsTheLaterSamplesOfEachSimulation) {
  const DataSetReader r(data());
  TrainingSampleDef all;
  all.every = 2;
  const int first = r.sample_step(r.simulations()[0].sample_begin + 5);  // the 6th sample's step
  TrainingSampleDef late = all;
  late.first_step = first;
  const auto a = load_training_samples(r, all);
  const auto b = load_training_samples(r, late);
  std::size_t expected = 0;
  for (const DataSetSimulation& sim : r.simulations()) {
    std::int64_t kept = 0;
    for (std::int64_t k = 0; k < sim.samples; ++k) kept += r.sample_step(sim.sample_begin + k) >= first;
    expected += static_cast<std::size_t>((kept + 1) / 2);
  }
  EXPECT_EQ(b.size(), expected);
  EXPECT_LT(b.size(), a.size());
  // The first kept sample of simulation 0 is the one of step `first`.
  const auto want = r.training_samples(std::vector<std::int64_t>{r.simulations()[0].sample_begin + 5},
                                       r.simulations()[0].index);
  for (std::size_t i = 0; i < want[0].features.size(); ++i) ASSERT_EQ(b[0].features[i], want[0].features[i]);
  late.first_step = 1 << 20;  // past every step
  EXPECT_THROW((void)load_training_samples(r, late), ConfigError);
  late.first_step = -1;
  EXPECT_THROW((void)load_training_samples(r, late), ConfigError);
}

// OUT is rewritten only when an epoch improves; OUT.ckpt and the CSV after every epoch; a
// resumed run starts from the best of its history.
TEST_F(TrainCheckpoint, OutputsKeepTheBestModelAndTheLatestState) {
  const DataSetReader r(data());
  const ArchSpec arch = default_arch(2, 0.0);
  Model model(arch, model_grid_for(r, LabelDef{}), r.feature_channels());
  const RunIdentity id = training_run_identity(r, arch.to_toml(), TrainDef{}, TrainingSampleDef{});
  const fs::path out = dir_ / "best.h5";
  TrainingOutputs files(out, id, data(), nullptr);
  EXPECT_EQ(files.best_epoch(), -1);
  EXPECT_EQ(files.checkpoint_path(), fs::path(out.string() + ".ckpt"));
  TrainState st;
  st.rng_type = "mt19937";
  const double losses[] = {2.0, 1.0, 3.0};
  for (int e = 0; e < 3; ++e) {
    const EpochReport rep{e, 9.0, losses[e], 0.01, 0.1};
    st.history.push_back(rep);
    st.epochs_done = e + 1;
    EXPECT_EQ(files.record_epoch(model, rep, st), e < 2) << e;
    const H5File best = H5File::open_read(out.string());
    EXPECT_EQ(best.attribute<std::int32_t>("/training", "epoch"), e < 1 ? 1 : 2);  // unchanged by epoch 3
    EXPECT_EQ(read_train_state(H5File::open_read(files.checkpoint_path().string()), id).epochs_done, e + 1);
  }
  EXPECT_EQ(files.best_epoch(), 1);
  EXPECT_EQ(files.best_score(), 1.0);
  EXPECT_EQ(H5File::open_read(out.string()).attribute_string("/training", "data"), data());
  const TrainingOutputs resumed(out, id, data(), &st);
  EXPECT_EQ(resumed.best_epoch(), 1);
  files.finish(st.history);
  const std::string csv = [&] {
    std::ifstream in(files.loss_csv_path());
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  EXPECT_EQ(csv, loss_csv(st.history));
  files.remove_checkpoint();
  EXPECT_FALSE(fs::exists(files.checkpoint_path()));
  EXPECT_TRUE(fs::exists(out));
}

TEST(TrainingData, ArchitecturesByName) {
  EXPECT_TRUE(is_builtin_arch(""));
  EXPECT_TRUE(is_builtin_arch("seed-dense"));
  EXPECT_FALSE(is_builtin_arch("my.toml"));
  EXPECT_EQ(select_arch("default", 2, 61, 61, 0.2).to_toml(), default_arch(2, 0.2).to_toml());
  EXPECT_EQ(select_arch("seed-dense", 2, 21, 21, 0.0).to_toml(), seed_dense_arch(2, 21, 21, 0.0).to_toml());
  EXPECT_THROW((void)select_arch("/no/such/arch.toml", 2, 61, 61, 0.1), ConfigError);
}

TEST(TrainingData, LossCsvAndScores) {
  std::vector<EpochReport> h{{0, 2.0, 1.5, 0.01, 1.25}, {1, 1.0, NAN, 0.005, 2.0}};
  EXPECT_EQ(epoch_score(h[0]), 1.5);
  EXPECT_EQ(epoch_score(h[1]), 1.0);  // no validation split: the training loss
  const std::string csv = loss_csv(h);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "epoch,train_loss,validation_loss,learning_rate,seconds");
  EXPECT_NE(csv.find("\n1,2,1.5,0.01,1.2500\n"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n2,1,nan,0.005,2.0000\n"), std::string::npos) << csv;
}

}  // namespace
}  // namespace dc
