// generate_data_set (data_set_generation.hpp): the file does not depend on the thread
// count, an interrupted run resumes to the same file, and the settings are checked.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cnn/small_data_set.hpp"
#include "dc/cnn/data_set_generation.hpp"
#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "h5_compare.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("dc_generation_test_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
  [[nodiscard]] std::string file(const std::string& name) const { return (path / name).string(); }
};

DataSetGenerationDef small(const std::string& out, int threads) {
  DataSetGenerationDef d;
  d.params = test::small_data_set_params(12, 30, 5, 8, 12);
  d.out = out;
  d.simulations = 4;
  d.threads = threads;
  return d;
}

TEST(DataSetGeneration, FileIsIndependentOfTheThreadCount) {
  TempDir dir;
  int committed = 0, last = -1, first_seen = -1;
  DataSetGenerationHooks hooks;
  hooks.on_start = [&](int first, int threads) {
    first_seen = first;
    EXPECT_EQ(threads, 1);
  };
  hooks.on_committed = [&](const SimulationRecord& r) {
    EXPECT_EQ(r.index, last + 1);  // strictly in order
    last = r.index;
    ++committed;
  };
  const DataSetGenerationReport one = generate_data_set(small(dir.file("one.h5"), 1), hooks);
  EXPECT_EQ(first_seen, 0);
  EXPECT_EQ(committed, 4);
  EXPECT_TRUE(one.finished);
  EXPECT_EQ(one.path, dir.file("one.h5"));
  EXPECT_EQ(one.completed, 4);
  EXPECT_EQ(one.steps, 4 * 30);
  EXPECT_FALSE(fs::exists(dir.file("one.h5.partial")));
  const DataSetGenerationReport three = generate_data_set(small(dir.file("three.h5"), 3));
  EXPECT_EQ(three.threads, 3);
  EXPECT_EQ(three.samples, one.samples);
  EXPECT_EQ(three.worst_residual, one.worst_residual);
  const H5File a = H5File::open_read(dir.file("one.h5")), b = H5File::open_read(dir.file("three.h5"));
  test::expect_same_datasets(a, b);
  const DataSetReader r(dir.file("one.h5"));
  EXPECT_EQ(static_cast<int>(r.simulations().size()), 4);
  EXPECT_EQ(r.samples(), one.samples);
}

TEST(DataSetGeneration, InterruptedRunResumesToTheSameFile) {
  TempDir dir;
  generate_data_set(small(dir.file("ref.h5"), 2));
  // Stop once the first simulation is committed: the rest is dropped, OUT.partial names the
  // run and no manifest is written.
  std::atomic<bool> stop{false};
  DataSetGenerationHooks hooks;
  hooks.keep_going = [&] { return !stop.load(); };
  hooks.on_committed = [&](const SimulationRecord&) { stop = true; };
  const DataSetGenerationReport cut = generate_data_set(small(dir.file("cut.h5"), 1), hooks);
  EXPECT_FALSE(cut.finished);
  EXPECT_GE(cut.completed, 1);
  EXPECT_LT(cut.completed, 4);
  EXPECT_TRUE(fs::exists(dir.file("cut.h5.partial")));
  EXPECT_TRUE(fs::is_directory(cut.path));
  EXPECT_FALSE(fs::exists(dir.file("cut.h5")));
  // Without resume a stale partial is refused; with it the run completes.
  EXPECT_THROW(generate_data_set(small(dir.file("cut.h5"), 2)), ConfigError);
  DataSetGenerationDef again = small(dir.file("cut.h5"), 3);
  again.resume = true;
  const DataSetGenerationReport done = generate_data_set(again);
  EXPECT_TRUE(done.finished);
  EXPECT_EQ(done.first, cut.completed);
  EXPECT_EQ(done.completed, 4);
  const H5File a = H5File::open_read(dir.file("ref.h5")), b = H5File::open_read(dir.file("cut.h5"));
  test::expect_same_datasets(a, b);
}

TEST(DataSetGeneration, SettingsAndFilesAreChecked) {
  TempDir dir;
  DataSetGenerationDef d = small(dir.file("x.h5"), 1);
  d.simulations = 0;
  EXPECT_THROW(generate_data_set(d), ConfigError);
  d = small("", 1);
  EXPECT_THROW(generate_data_set(d), ConfigError);
  d = small(dir.file("x.h5"), -1);
  EXPECT_THROW(generate_data_set(d), ConfigError);
  d = small(dir.file("x.h5"), 1);
  d.resume = true;  // nothing to resume
  EXPECT_THROW(generate_data_set(d), ConfigError);
  { std::ofstream(dir.file("x.h5")) << "x"; }
  d.resume = false;
  EXPECT_THROW(generate_data_set(d), ConfigError);  // exists, no force
  EXPECT_FALSE(fs::exists(dir.file("x.h5.partial")));
  d.force = true;
  d.simulations = 1;
  EXPECT_TRUE(generate_data_set(d).finished);
  EXPECT_NO_THROW(DataSetReader{dir.file("x.h5")});
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The one run folder under OUT.shards.
fs::path run_folder(const std::string& out) {
  const fs::directory_iterator it(out + ".shards");
  return it->path();
}

// A kill while a shard is being written leaves its temporary name: resume removes it (and
// says how many), computes the simulation again, and the data set equals an uninterrupted one.
TEST(DataSetGeneration, ResumeDiscardsAnIncompleteShard) {
  TempDir dir;
  generate_data_set(small(dir.file("ref.h5"), 1));
  DataSetGenerationHooks hooks;
  std::atomic<bool> stop{false};
  hooks.keep_going = [&] { return !stop.load(); };
  hooks.on_committed = [&](const SimulationRecord& r) { stop = r.index >= 1; };
  ASSERT_FALSE(generate_data_set(small(dir.file("cut.h5"), 1), hooks).finished);
  const fs::path folder = run_folder(dir.file("cut.h5"));
  { std::ofstream(folder / "sim-000002.h5.tmp") << "\x89HDF half a file"; }
  DataSetGenerationDef again = small(dir.file("cut.h5"), 1);
  again.resume = true;
  const DataSetGenerationReport done = generate_data_set(again);
  EXPECT_EQ(done.discarded, 1);
  EXPECT_EQ(done.first, 2);
  EXPECT_TRUE(done.finished);
  EXPECT_FALSE(fs::exists(folder / "sim-000002.h5.tmp"));
  EXPECT_FALSE(fs::exists(dir.file("cut.h5.partial")));
  test::expect_same_datasets(H5File::open_read(dir.file("ref.h5")), H5File::open_read(dir.file("cut.h5")));
}

// The manifest's bulk datasets are virtual: a missing or replaced shard would read as fill
// values, so the reader checks every shard first and names the missing one.
TEST(DataSetGeneration, ReaderRefusesAManifestWithAMissingShard) {
  TempDir dir;
  generate_data_set(small(dir.file("d.h5"), 1));
  const fs::path folder = run_folder(dir.file("d.h5"));
  fs::rename(folder / "sim-000002.h5", folder / "moved.h5");
  try {
    const DataSetReader r(dir.file("d.h5"));
    ADD_FAILURE() << "a manifest with a missing shard was read";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("sim-000002.h5 is missing"), std::string::npos) << e.what();
  }
  fs::copy_file(folder / "sim-000001.h5", folder / "sim-000002.h5");  // another shard's bytes
  EXPECT_THROW(DataSetReader{dir.file("d.h5")}, IoError);
}

// --force replaces a data set only once the new one is complete: an interrupted replacement
// leaves the old manifest and its shards readable.
TEST(DataSetGeneration, ForceKeepsTheOldDataSetUntilTheNewOneIsComplete) {
  TempDir dir;
  generate_data_set(small(dir.file("d.h5"), 1));
  const std::string before = slurp(dir.file("d.h5"));
  DataSetGenerationDef replace = small(dir.file("d.h5"), 1);
  replace.force = true;
  replace.params.seed = 99;
  DataSetGenerationHooks hooks;
  std::atomic<bool> stop{false};
  hooks.keep_going = [&] { return !stop.load(); };
  hooks.on_committed = [&](const SimulationRecord&) { stop = true; };
  ASSERT_FALSE(generate_data_set(replace, hooks).finished);
  EXPECT_EQ(slurp(dir.file("d.h5")), before);
  EXPECT_EQ(DataSetReader(dir.file("d.h5")).params().seed, test::small_data_set_params(12, 30, 5, 8, 12).seed);
  replace.resume = true;
  ASSERT_TRUE(generate_data_set(replace).finished);
  EXPECT_EQ(DataSetReader(dir.file("d.h5")).params().seed, 99u);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.file("d.h5.shards")), fs::directory_iterator{}), 1);
}

// A kill between the manifest's rename and the removal of OUT.partial leaves a complete data
// set and a marker: --resume then only finishes the cleanup (no "OUT exists" refusal).
TEST(DataSetGeneration, ResumeAfterTheManifestWasWrittenFinishes) {
  TempDir dir;
  generate_data_set(small(dir.file("d.h5"), 1));
  const std::string run = run_folder(dir.file("d.h5")).filename().string();
  { std::ofstream(dir.file("d.h5.partial")) << "deepcontact-generate run " << run << "\n"; }
  DataSetGenerationDef again = small(dir.file("d.h5"), 1);
  again.resume = true;
  const DataSetGenerationReport r = generate_data_set(again);
  EXPECT_TRUE(r.finished);
  EXPECT_EQ(r.first, 4);
  EXPECT_FALSE(fs::exists(dir.file("d.h5.partial")));
  EXPECT_EQ(DataSetReader(dir.file("d.h5")).simulations().size(), 4u);
}

}  // namespace
}  // namespace dc
