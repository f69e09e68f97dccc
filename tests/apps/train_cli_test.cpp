// deepcontact train as a process, on a tiny generated data set (3 simulations of 10–14
// circles in a 12 × 12 box, 120 steps — every 3rd used —, 25 × 25 grid): a short run writes a loadable model
// with the data set's grid, the loss CSV/PNG; kill -9 and SIGINT followed by --resume
// complete and give the bit-identical model of an uninterrupted run; bad inputs fail with a
// one-line message and a non-zero status.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "cli_helpers.hpp"
#include "dc/cnn/data_set.hpp"
#include "dc/io/h5.hpp"
#include "dc/learning/model_file.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;
using test::ChildLog;
using test::slurp;
using test::spawn_cli;
using test::wait_exit;
using test::wait_for;

const std::string kFamily =
    " --set world.width=12 --set world.height=12 --set bodies.mean=[6.0,6.0] --set bodies.sigma=2.0 --seed 5"
    " --count 10..14 --steps 120 --threads 1";
// Small, fast, single-threaded (bit-equality needs equal thread counts).
const std::string kTrain = " --batch 8 --every 3 --threads 1 --seed 3 --no-plot";

using test::TempDir;
using Dir = TempDir;

using Result = test::CliResult;


/// The tiny data sets, generated once per test binary run: the default channels, without
/// contact_density, or the residual model's channels (with lambda_prev_n/t).
enum class Channels { Default, NoDensity, Residual };
std::string data_set(Channels kind);
std::string data_set(bool with_density = true) { return data_set(with_density ? Channels::Default : Channels::NoDensity); }
std::string data_set(Channels kind) {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("dc_train_cli_data_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  static const struct Cleanup {
    fs::path d;
    ~Cleanup() { fs::remove_all(d); }
  } cleanup{dir};
  const char* name = kind == Channels::Default ? "data.h5" : kind == Channels::NoDensity ? "nodensity.h5" : "residual.h5";
  const char* channels = kind == Channels::Default     ? ""
                         : kind == Channels::NoDensity ? " --channels mass,vx,vy,omega"
                                                       : " --channels mass,vx,vy,omega,contact_density,lambda_prev_n,"
                                                         "lambda_prev_t,vrel_n,vrel_t,gap";
  const std::string out = (dir / name).string();
  if (!fs::exists(out)) {
    const std::string cmd =
        std::string(DC_CLI) + " generate --sims 3" + kFamily + channels + " --out " + out + " >/dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  return out;
}

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

/// Every parameter of two model files, bit for bit.
void expect_same_weights(const std::string& a, const std::string& b) {
  Model ma = load_model(a), mb = load_model(b);
  const auto pa = ma.network().parameters(), pb = mb.network().parameters();
  ASSERT_EQ(pa.size(), pb.size());
  for (std::size_t i = 0; i < pa.size(); ++i) {
    ASSERT_EQ(pa[i].value->size(), pb[i].value->size());
    EXPECT_EQ(0, std::memcmp(pa[i].value->data(), pb[i].value->data(), sizeof(float) * pa[i].value->size()))
        << pa[i].name;
  }
  EXPECT_EQ(ma.input_stats.mean, mb.input_stats.mean);
  EXPECT_EQ(ma.output_stats.std, mb.output_stats.std);
}

TEST(TrainCli, ShortRunWritesAModelForTheDataSetsGrid) {
  Dir dir;
  const std::string model = dir / "m.h5";
  const Result r = test::run_cli("train --data " + data_set() + " --out " + model + " --epochs 2 --batch 8 --every 3 --threads 1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("epoch   1/2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("epoch   2/2"), std::string::npos) << r.out;
  Model m = load_model(model);
  EXPECT_EQ(m.grid().nx(), 25);
  EXPECT_EQ(m.grid().ny(), 25);
  EXPECT_EQ(feature_channel_names(m.grid().image.channels), DataSetReader(data_set()).feature_channel_names());
  EXPECT_EQ(m.grid().label_channels, (std::vector<std::string>{"lambda_n", "lambda_t"}));
  EXPECT_EQ(m.network().input_shape().c, 5);
  // Standardisation is learned (not the identity) and stored.
  EXPECT_NE(m.output_stats.std[0], 1.0f);
  EXPECT_EQ(lines(slurp(model + ".loss.csv")), 3);  // header + 2 epochs
  if (fs::exists("/usr/bin/python3")) {
    EXPECT_TRUE(fs::exists(model + ".loss.png")) << r.err;
  }
  EXPECT_FALSE(fs::exists(model + ".ckpt"));  // finished: no checkpoint left behind
  // An existing model is not overwritten without --force.
  const Result again = test::run_cli("train --data " + data_set() + " --out " + model + " --epochs 1");
  EXPECT_NE(again.exit_code, 0);
  EXPECT_EQ(lines(again.err), 1) << again.err;
}

TEST(TrainCli, ContactWeightRunsAndNeedsTheDensityChannel) {
  Dir dir;
  Result r = test::run_cli("train --data " + data_set() + " --out " + (dir / "w.h5") + " --epochs 1 --contact-weight 4" +
                              kTrain);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("contact weight 4"), std::string::npos) << r.out;
  // The weight needs the contact_density channel.
  r = test::run_cli("train --data " + data_set(false) + " --out " + (dir / "x.h5") + " --epochs 1 --contact-weight 4" +
                       kTrain);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("contact_density"), std::string::npos) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
}

// --residual trains on label − lambda_prev and says so in the model; it needs those channels.
TEST(TrainCli, ResidualNeedsTheLambdaPrevChannelsAndIsStoredInTheModel) {
  Dir dir;
  Result r = test::run_cli("train --data " + data_set(Channels::Residual) + " --out " + (dir / "r.h5") +
                              " --epochs 1 --residual --contact-weight 4" + kTrain);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("residual labels"), std::string::npos) << r.out;
  Model m = load_model(dir / "r.h5");
  EXPECT_EQ(m.grid().labels.kind, LabelKind::Residual);
  EXPECT_EQ(m.network().input_shape().c, 10);
  // The same data without --residual gives an absolute model.
  r = test::run_cli("train --data " + data_set(Channels::Residual) + " --out " + (dir / "a.h5") + " --epochs 1" + kTrain);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(load_model(dir / "a.h5").grid().labels.kind, LabelKind::Absolute);
  // A data set without lambda_prev channels: one-line error naming them.
  r = test::run_cli("train --data " + data_set() + " --out " + (dir / "x.h5") + " --epochs 1 --residual" + kTrain);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("lambda_prev_n"), std::string::npos) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
}

TEST(TrainCli, PgsResidualLossTrainsFromAResidualInitModel) {
  Dir dir;
  const std::string data = data_set(Channels::Residual);
  Result r = test::run_cli("train --data " + data + " --out " + (dir / "r.h5") + " --epochs 1 --residual" + kTrain);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_cli("train --data " + data + " --out " + (dir / "p.h5") +
                    " --epochs 1 --loss pgs-residual --unroll 3 --init " + (dir / "r.h5") + kTrain);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("epoch   1/1"), std::string::npos) << r.out;
  Model m = load_model(dir / "p.h5");
  EXPECT_EQ(m.grid().labels.kind, LabelKind::Residual);
  EXPECT_EQ(lines(slurp(dir / "p.h5.loss.csv")), 2);
  // Without --init, or from an absolute model: one-line errors.
  r = test::run_cli("train --data " + data + " --out " + (dir / "x.h5") + " --epochs 1 --loss pgs-residual" + kTrain);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--init"), std::string::npos) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  r = test::run_cli("train --data " + data + " --out " + (dir / "a.h5") + " --epochs 1" + kTrain);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_cli("train --data " + data + " --out " + (dir / "y.h5") + " --epochs 1 --loss pgs-residual --init " +
                    (dir / "a.h5") + kTrain);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("residual model"), std::string::npos) << r.err;
  r = test::run_cli("train --data " + data + " --out " + (dir / "y.h5") + " --epochs 1 --loss nonsense --init " +
                    (dir / "r.h5") + kTrain);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--loss"), std::string::npos) << r.err;
}

// --gain: a gain model from a residual --init, through PGS only; it starts at builtin (its
// output layer zeroed: the epoch-0 objective is 0) and is stored as label kind "gain".
TEST(TrainCli, PgsGainTrainsAGainModelFromAResidualInit) {
  Dir dir;
  const std::string data = data_set(Channels::Residual);
  Result r = test::run_cli("train --data " + data + " --out " + (dir / "r.h5") + " --epochs 1 --residual" + kTrain);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_cli("train --data " + data + " --out " + (dir / "g.h5") +
                    " --epochs 1 --loss pgs-distance --unroll 3 --gain --init " + (dir / "r.h5") + kTrain);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Model m = load_model(dir / "g.h5");
  EXPECT_EQ(m.grid().labels.kind, LabelKind::Gain);
  EXPECT_EQ(m.grid().labels.scale, 0.0);
  EXPECT_NE(r.out.find("the --init model: validation objective 0.0000"), std::string::npos) << r.out;
  // One epoch on this tiny set ends worse than builtin's J = 0 (validation J +0.49): the
  // written model is the best trained epoch, and the user is told it is worse than --init.
  EXPECT_NE(r.err.find("warning: no epoch beat the --init model"), std::string::npos) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  // Continuing a gain model needs --gain; --gain needs a pgs-* loss: one-line errors.
  r = test::run_cli("train --data " + data + " --out " + (dir / "x.h5") +
                    " --epochs 1 --loss pgs-distance --unroll 3 --init " + (dir / "g.h5") + kTrain);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--gain"), std::string::npos) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  r = test::run_cli("train --data " + data + " --out " + (dir / "y.h5") + " --epochs 1 --gain" + kTrain);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--gain"), std::string::npos) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.h5") || fs::exists(dir / "y.h5"));
}

// --loss pgs-field regresses the gain grid on the least-squares field G* and is validated by
// pgs-distance (the init message says which loss validation measures); --field-iterations
// below 1 is a one-line error that writes nothing.
TEST(TrainCli, PgsFieldTrainsAGainModelValidatedByPgsDistance) {
  Dir dir;
  const std::string data = data_set(Channels::Residual);
  Result r = test::run_cli("train --data " + data + " --out " + (dir / "r.h5") + " --epochs 1 --residual" + kTrain);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_cli("train --data " + data + " --out " + (dir / "f.h5") +
                    " --epochs 1 --loss pgs-field --field-iterations 3 --unroll 3 --gain --lr 1e-4 --init " +
                    (dir / "r.h5") + kTrain);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(load_model(dir / "f.h5").grid().labels.kind, LabelKind::Gain);
  EXPECT_NE(r.out.find("log-units of the pgs-distance loss"), std::string::npos) << r.out;
  r = test::run_cli("train --data " + data + " --out " + (dir / "z.h5") +
                    " --epochs 1 --loss pgs-field --field-iterations 0 --unroll 3 --gain --init " + (dir / "r.h5") +
                    kTrain);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("field"), std::string::npos) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "z.h5"));
}

// The --init model may come from another box (the cnn starter runs a fully convolutional
// model on any grid): trained on the 12 × 12 box's 25 × 25 grid, fine-tuned through PGS on a
// 16 × 12 box's data (33 × 25); the written model carries the new data set's grid. Another
// node spacing is a one-line error.
TEST(TrainCli, PgsLossStartsFromAModelOfAnotherBox) {
  Dir dir;
  Result r = test::run_cli("train --data " + data_set(Channels::Residual) + " --out " + (dir / "r.h5") +
                           " --epochs 1 --residual" + kTrain);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string ch = " --channels mass,vx,vy,omega,contact_density,lambda_prev_n,lambda_prev_t,vrel_n,vrel_t,gap";
  const std::string wide = " --set world.width=16 --set world.height=12 --set bodies.mean=[8.0,6.0] --set bodies.sigma=2.0"
                           " --seed 9 --count 10..14 --steps 60 --threads 1";
  r = test::run_cli("generate --sims 2" + wide + ch + " --out " + (dir / "wide.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_cli("train --data " + (dir / "wide.h5") + " --out " + (dir / "p.h5") +
                    " --epochs 1 --loss pgs-residual --unroll 3 --init " + (dir / "r.h5") + kTrain);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Model m = load_model(dir / "p.h5");
  EXPECT_EQ(m.grid().nx(), 33);
  EXPECT_EQ(m.grid().ny(), 25);
  EXPECT_EQ(m.network().input_shape().w, 33);
  r = test::run_cli("generate --sims 1" + wide + ch + " --grid poly6:0.4:0.355 --out " + (dir / "fine.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_cli("train --data " + (dir / "fine.h5") + " --out " + (dir / "q.h5") +
                    " --epochs 1 --loss pgs-residual --unroll 3 --init " + (dir / "r.h5") + kTrain);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("node spacing"), std::string::npos) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
}

TEST(TrainCli, KillNineThenResumeEqualsAnUninterruptedRun) {
  Dir dir;
  const std::string args = "train --data " + data_set() + " --epochs 8" + kTrain;
  const Result ref = test::run_cli(args + " --out " + (dir / "ref.h5"));
  ASSERT_EQ(ref.exit_code, 0) << ref.err;

  const std::string out = dir / "killed.h5", log = dir / "log.txt";
  const pid_t pid = spawn_cli(args + " --out " + out, log, ChildLog::StdoutAndStderr);
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for(log, "epoch   2/8", pid)) << slurp(log);
  ::kill(pid, SIGKILL);
  EXPECT_EQ(wait_exit(pid), -SIGKILL) << "the run finished before it could be killed";
  ASSERT_TRUE(fs::exists(out + ".ckpt"));
  ASSERT_TRUE(fs::exists(out));  // the best model so far is always on disk
  (void)load_model(out);

  const Result resumed = test::run_cli(args + " --out " + out + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("resuming after epoch"), std::string::npos) << resumed.out;
  EXPECT_NE(resumed.out.find("epoch   8/8"), std::string::npos) << resumed.out;
  EXPECT_EQ(lines(slurp(out + ".loss.csv")), 9);
  expect_same_weights(dir / "ref.h5", out);
  EXPECT_EQ(slurp(dir / "ref.h5.loss.csv").substr(0, 60), slurp(out + ".loss.csv").substr(0, 60));
}

TEST(TrainCli, SigintStopsCleanlyAndResumeCompletes) {
  Dir dir;
  const std::string args = "train --data " + data_set() + " --epochs 8" + kTrain;
  const Result ref = test::run_cli(args + " --out " + (dir / "ref.h5"));
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  const std::string out = dir / "int.h5", log = dir / "log.txt";
  const pid_t pid = spawn_cli(args + " --out " + out, log, ChildLog::StdoutAndStderr);
  ASSERT_TRUE(wait_for(log, "epoch   1/8", pid)) << slurp(log);
  ::kill(pid, SIGINT);
  EXPECT_EQ(wait_exit(pid), 130) << slurp(log);
  EXPECT_NE(slurp(log).find("--resume"), std::string::npos) << slurp(log);
  const Result resumed = test::run_cli(args + " --out " + out + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expect_same_weights(dir / "ref.h5", out);
}

// A training split larger than --shuffle-buffer streams from disk in the buffered order: a
// SIGTERM stops it before the next minibatch (exit 143; the last finished epoch is on disk),
// and the resumed run equals the uninterrupted one bit for bit (the plan is drawn from the
// checkpointed random stream).
TEST(TrainCli, BufferedStreamStopsOnSigtermAndResumesToTheSameModel) {
  Dir dir;
  const std::string args = "train --data " + data_set() + " --epochs 5 --shuffle-buffer 10" + kTrain;
  const Result ref = test::run_cli(args + " --out " + (dir / "ref.h5"));
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  EXPECT_NE(ref.out.find("shuffle buffer 10 samples"), std::string::npos) << ref.out;
  const Result whole = test::run_cli("train --data " + data_set() + " --epochs 5" + kTrain + " --out " + (dir / "whole.h5"));
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  EXPECT_NE(slurp(dir / "ref.h5.loss.csv").substr(0, 80), slurp(dir / "whole.h5.loss.csv").substr(0, 80))
      << "a buffer smaller than the split changes the visiting order";

  const std::string out = dir / "term.h5", log = dir / "log.txt";
  const pid_t pid = spawn_cli(args + " --out " + out, log, ChildLog::StdoutAndStderr);
  ASSERT_TRUE(wait_for(log, "epoch   1/5", pid)) << slurp(log);
  ::kill(pid, SIGTERM);
  EXPECT_EQ(wait_exit(pid), 143) << slurp(log);
  const Result resumed = test::run_cli(args + " --out " + out + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expect_same_weights(dir / "ref.h5", out);
}

TEST(TrainCli, BadInputsFailWithOneLine) {
  Dir dir;
  const auto expect_error = [&](const std::string& args, const std::string& needle) {
    const Result r = test::run_cli(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(lines(r.err), 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
  };
  const std::string out = " --out " + (dir / "m.h5");
  expect_error("train --data " + (dir / "missing.h5") + out, "missing.h5");
  { std::ofstream(dir / "text.h5") << "not a data set\n"; }
  expect_error("train --data " + (dir / "text.h5") + out, "text.h5");
  expect_error("train --data " + data_set() + out + " --resume", "--resume");
  expect_error("train --data " + data_set() + out + " --epochs 0", "epochs");
  expect_error("train --data " + data_set() + out + " --schedule sometimes", "schedule");
  expect_error("train --data " + data_set() + out + " --arch nothere.toml", "--arch");
  expect_error("train --data " + data_set() + out + " --label-scale -1", "--label-scale");
  expect_error("train --data " + data_set() + out + " --deadzone 5", "--residual");
  expect_error("train --data " + data_set(Channels::Residual) + out + " --residual --deadzone -2", "--deadzone");
  expect_error("train --data " + data_set() + out + " --shuffle-buffer 0", "shuffle_buffer");

  // A checkpoint of another run (other lr), then one of another format version.
  const std::string base = "train --data " + data_set() + " --epochs 6" + kTrain + out;
  const pid_t pid = spawn_cli(base, dir / "log.txt", ChildLog::StdoutAndStderr);
  ASSERT_TRUE(wait_for(dir / "log.txt", "epoch   1/6", pid)) << slurp(dir / "log.txt");
  ::kill(pid, SIGKILL);
  (void)wait_exit(pid);
  ASSERT_TRUE(fs::exists(dir / "m.h5.ckpt"));
  expect_error(base + " --resume --lr 0.1", "lr");
  {
    H5File f = H5File::open_rw(dir / "m.h5.ckpt");
    f.set_attribute<std::int32_t>("/", "format_version", 99);
  }
  expect_error(base + " --resume", "version");
}

}  // namespace
}  // namespace dc
