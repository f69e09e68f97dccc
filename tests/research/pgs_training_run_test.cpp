// A run of train --loss pgs-* (pgs_training_run.hpp) on a small generated data set: the hooks
// come in order with the run's figures, OUT holds the best epoch and OUT.loss.csv one line per
// epoch, a gain run from a residual --init starts at builtin (J = 0) and writes a gain model,
// a stop during the replay writes nothing, and bad runs are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cnn/small_data_set.hpp"
#include "dc/cnn/data_set_generation.hpp"
#include "dc/core/error.hpp"
#include "dc/learning/model_file.hpp"
#include "dc/research/pgs_training_run.hpp"
#include "learning/small_archs.hpp"
#include "temp_dir.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

class PgsTrainingRunTest : public ::testing::Test {
 protected:
  /// A 2-simulation data set with the residual channels and a residual model of its grid.
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    DataSetGenerationDef d;
    d.params = test::small_data_set_params(12, 40, 11, 10, 14);
    d.params.image.channels = residual_feature_channels();
    d.out = dir_->file("data.h5");
    d.simulations = 2;
    d.threads = 1;
    generate_data_set(d);
    ModelGrid grid;
    grid.image = d.params.image;
    grid.labels.kind = LabelKind::Residual;
    Model init(test::fast_head_arch(false), grid, static_cast<int>(d.params.image.channels.size()));
    save_model(init, dir_->file("init.h5"));
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static PgsTrainingRunDef def(const std::string& out) {
    PgsTrainingRunDef d;
    d.data = dir_->file("data.h5");
    d.init = dir_->file("init.h5");
    d.out = dir_->file(out);
    d.train.loss = PgsLoss::Residual;
    d.train.unroll = 3;
    d.train.epochs = 2;
    d.train.batch = 4;
    d.train.validation_fraction = 0.5;
    d.every = 4;
    return d;
  }
  static inline test::TempDir* dir_ = nullptr;
};

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream f(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(f, line);) out.push_back(line);
  return out;
}

TEST_F(PgsTrainingRunTest, ReportsInOrderAndKeepsTheBestEpoch) {
  const PgsTrainingRunDef d = def("p.h5");
  std::vector<std::string> calls;
  std::vector<PgsEpochReport> epochs;
  std::vector<bool> improved;
  PgsTrainingHooks h;
  h.on_replay_start = [&] { calls.push_back("start"); };
  h.on_replayed = [&](const PgsReplayReport& r) {
    calls.push_back("replayed");
    EXPECT_EQ(r.simulations, 2u);
    EXPECT_GT(r.samples, 0u);
  };
  h.on_init = [&](const PgsInitReport& r) {
    calls.push_back("init");
    EXPECT_TRUE(std::isfinite(r.objective));
  };
  h.on_epoch = [&](const PgsEpochReport& r, bool better) {
    calls.push_back("epoch");
    EXPECT_TRUE(fs::exists(d.out + ".loss.csv"));  // written before the hook
    epochs.push_back(r);
    improved.push_back(better);
  };
  const PgsTrainingOutcome o = run_pgs_training(d, h);
  EXPECT_EQ(calls, (std::vector<std::string>{"start", "replayed", "init", "epoch", "epoch"}));
  ASSERT_FALSE(o.replay_interrupted);
  ASSERT_EQ(o.epochs, 2u);
  // OUT holds the epoch of the lowest validation objective, the first of equals.
  const int best = epochs[1].validation_objective < epochs[0].validation_objective ? 1 : 0;
  EXPECT_EQ(o.best_epoch, best);
  EXPECT_EQ(o.best, epochs[best].validation_objective);
  EXPECT_TRUE(improved[0]);
  EXPECT_EQ(improved[1], best == 1);
  EXPECT_DOUBLE_EQ(o.seconds, epochs[0].seconds + epochs[1].seconds);
  EXPECT_EQ(o.worse_than_init(), o.best > o.init_objective);
  EXPECT_EQ(load_model(d.out).grid().labels.kind, LabelKind::Residual);
  const std::vector<std::string> csv = lines_of(d.out + ".loss.csv");
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv[0], "epoch,train_objective,validation_objective,validation_improved,seconds");
  EXPECT_EQ(csv[1].rfind("1,", 0), 0u);
  EXPECT_EQ(csv[2].rfind("2,", 0), 0u);
  // OUT exists now: refused without force.
  EXPECT_THROW((void)run_pgs_training(d), ConfigError);
}

TEST_F(PgsTrainingRunTest, GainFromAResidualInitStartsAtBuiltin) {
  PgsTrainingRunDef d = def("g.h5");
  d.gain = true;
  d.train.loss = PgsLoss::Distance;
  d.train.epochs = 1;
  const PgsTrainingOutcome o = run_pgs_training(d);
  EXPECT_EQ(o.init_objective, 0.0);
  EXPECT_EQ(load_model(d.out).grid().labels.kind, LabelKind::Gain);
  // Continuing that gain model without gain is refused.
  PgsTrainingRunDef cont = def("g2.h5");
  cont.init = d.out;
  EXPECT_THROW((void)run_pgs_training(cont), ConfigError);
}

TEST_F(PgsTrainingRunTest, AStopDuringTheReplayWritesNothing) {
  const PgsTrainingRunDef d = def("stopped.h5");
  PgsTrainingHooks h;
  h.keep_going = [] { return false; };
  bool replayed = false;
  h.on_replayed = [&](const PgsReplayReport&) { replayed = true; };
  const PgsTrainingOutcome o = run_pgs_training(d, h);
  EXPECT_TRUE(o.replay_interrupted);
  EXPECT_FALSE(replayed);
  EXPECT_FALSE(fs::exists(d.out));
  EXPECT_FALSE(fs::exists(d.out + ".loss.csv"));
}

TEST_F(PgsTrainingRunTest, RefusesBadRuns) {
  PgsTrainingRunDef d = def("x.h5");
  d.init.clear();
  EXPECT_THROW(d.validate(), ConfigError);
  d = def("x.h5");
  d.every = 0;
  EXPECT_THROW(d.validate(), ConfigError);
  d = def("x.h5");
  d.deadzone = -1;
  EXPECT_THROW(d.validate(), ConfigError);
  d = def("x.h5");
  d.train.unroll = 0;
  EXPECT_THROW(d.validate(), ConfigError);
  d = def("x.h5");
  d.data = dir_->file("missing.h5");
  EXPECT_THROW((void)run_pgs_training(d), IoError);
  d = def("x.h5");
  d.train.time_limit = 1e-9;  // stops before the first minibatch: no finished epoch
  EXPECT_THROW((void)run_pgs_training(d), ConfigError);
}

}  // namespace
}  // namespace dc
