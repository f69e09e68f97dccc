// Data set: generator determinism, writer → reader round trip (layout, shapes, attributes,
// contacts), crash-consistent resume (cut back to committed simulations), reader errors.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cnn/small_data_set.hpp"
#include "dc/cnn/data_set.hpp"
#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "h5_compare.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

/// A small family: 10–14 circles in a 12 × 12 box, 40 steps, d = h = 0.5 (25 × 25 grid).
DataSetParams small_params() { return test::small_data_set_params(12, 40, 11, 10, 14); }

std::string temp_path(const std::string& name) {
  return (fs::temp_directory_path() / ("dc_data_set_test_" + std::to_string(::getpid()) + "_" + name)).string();
}

struct TempFile {
  std::string path;
  explicit TempFile(const std::string& name) : path(temp_path(name)) { fs::remove(path); }
  ~TempFile() { fs::remove(path); }
};

/// The three simulations of the small family, generated once for all tests.
const std::vector<SimulationRecord>& records() {
  static const std::vector<SimulationRecord> recs = [] {
    const SimulationGenerator g(small_params());
    std::vector<SimulationRecord> out;
    for (int i = 0; i < 3; ++i) out.push_back(*g.run(i));
    return out;
  }();
  return recs;
}

void write_all(const std::string& path, int count) {
  DataSetWriter w = DataSetWriter::create(path, small_params());
  for (int i = 0; i < count; ++i) w.append(records()[static_cast<std::size_t>(i)]);
  w.close();
}

using test::expect_same_datasets;

TEST(DataSet, SimulationsAreDeterministicAndFollowTheSeedFamily) {
  const DataSetParams p = small_params();
  const SimulationGenerator g(p);
  const SimulationRecord again = *g.run(1);
  const SimulationRecord& first = records()[1];
  EXPECT_EQ(again.features, first.features);
  EXPECT_EQ(again.labels, first.labels);
  EXPECT_EQ(again.lambda_star, first.lambda_star);
  EXPECT_EQ(again.position, first.position);
  for (const auto& r : records()) {
    EXPECT_EQ(r.seed, p.seed + static_cast<std::uint64_t>(r.index));
    EXPECT_GE(r.bodies, p.count_min);
    EXPECT_LE(r.bodies, p.count_max);
    EXPECT_GT(r.samples(), 10u);
    EXPECT_LT(r.max_residual, 1e-3);  // [N], PGS from the builtin start
    for (std::size_t s = 1; s < r.samples(); ++s) EXPECT_LT(r.step[s - 1], r.step[s]);
  }
  // The interruption hook: a generator asked to stop returns nothing.
  EXPECT_FALSE(g.run(0, [] { return false; }).has_value());
}

TEST(DataSet, WriterReaderRoundTripWithTheDocumentedLayout) {
  TempFile tmp("roundtrip.h5");
  write_all(tmp.path, 3);
  const DataSetParams p = small_params();
  {
    const H5File f = H5File::open_read(tmp.path);
    EXPECT_EQ(f.attribute_string("/", "format"), "deepcontact-dataset");
    EXPECT_EQ(f.attribute<std::int32_t>("/", "format_version"), kDataSetFormatVersion);
    EXPECT_EQ(f.attribute_string("/", "feature_channels"), "mass,vx,vy,omega,contact_density");
    EXPECT_EQ(f.attribute_string("/", "label_channels"), "lambda_n,lambda_t");
    EXPECT_EQ(f.attribute_string("/", "grid_kernel"), "poly6");
    EXPECT_EQ(f.attribute<std::int32_t>("/", "grid_nx"), 25);
    EXPECT_EQ(f.attribute<std::int32_t>("/", "grid_ny"), 25);
    EXPECT_EQ(f.attribute<std::int64_t>("/", "seed"), 11);
    std::size_t n = 0, B = 0, C = 0;
    for (const auto& r : records()) {
      n += r.samples();
      B += r.samples() * static_cast<std::size_t>(r.bodies);
      C += r.contacts();
    }
    EXPECT_EQ(f.shape("/samples/features"), (H5Shape{n, 5, 25, 25}));
    EXPECT_EQ(f.type("/samples/features"), H5Type::Float32);
    EXPECT_EQ(f.shape("/samples/labels"), (H5Shape{n, 2, 25, 25}));
    EXPECT_EQ(f.shape("/bodies/position"), (H5Shape{B, 2}));
    EXPECT_EQ(f.shape("/contacts/lambda_star"), (H5Shape{C, 2}));
    EXPECT_EQ(f.shape("/sims/seed"), (H5Shape{3}));
    const auto body_begin = f.read<std::int64_t>("/samples/body_begin");
    const auto body_count = f.read<std::int32_t>("/samples/body_count");
    for (std::size_t s = 1; s < n; ++s) EXPECT_EQ(body_begin[s], body_begin[s - 1] + body_count[s - 1]);
    EXPECT_EQ(static_cast<std::size_t>(body_begin[n - 1] + body_count[n - 1]), B);
  }
  const DataSetReader r(tmp.path);
  EXPECT_EQ(r.params().seed, p.seed);
  EXPECT_EQ(r.params().image.channels, p.image.channels);
  EXPECT_EQ(r.params().scene.time.steps, 40);
  EXPECT_EQ(r.nx(), 25);
  EXPECT_EQ(r.ny(), 25);
  ASSERT_EQ(r.simulations().size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const SimulationRecord& rec = records()[static_cast<std::size_t>(i)];
    const DataSetSimulation& s = r.simulations()[static_cast<std::size_t>(i)];
    EXPECT_EQ(s.seed, rec.seed);
    EXPECT_EQ(s.bodies, rec.bodies);
    EXPECT_EQ(s.samples, static_cast<std::int64_t>(rec.samples()));
    const int one[] = {i};
    const auto rows = r.samples_of(one);
    const Tensor f = r.features(rows), l = r.labels(rows);
    EXPECT_EQ(f.shape(), (Shape{static_cast<int>(rec.samples()), 5, 25, 25}));
    EXPECT_TRUE(std::equal(f.data(), f.data() + f.size(), rec.features.begin()));
    EXPECT_TRUE(std::equal(l.data(), l.data() + l.size(), rec.labels.begin()));
    EXPECT_EQ(r.sample_step(rows[3]), rec.step[3]);
    EXPECT_EQ(r.sample_simulation(rows[3]), i);
    // Contacts of one sample, with λ*.
    std::size_t c0 = 0;
    for (std::size_t k = 0; k < 3; ++k) c0 += static_cast<std::size_t>(rec.contact_count[k]);
    const SampleContacts c = r.contacts(rows[3]);
    ASSERT_EQ(c.point.size(), static_cast<std::size_t>(rec.contact_count[3]));
    EXPECT_EQ(c.point[0].x, rec.point[2 * c0]);
    EXPECT_EQ(c.lambda_n[0], rec.lambda_star[2 * c0]);
    EXPECT_EQ(c.lambda_t[0], rec.lambda_star[2 * c0 + 1]);
    EXPECT_EQ(c.body_b[0], rec.body_b[c0]);
  }
  // Non-consecutive selections come back in the requested order.
  const std::int64_t pick[] = {5, 2, 3};
  const Tensor f = r.features(pick);
  const Tensor all = r.features(r.samples_of(std::vector<int>{0}));
  EXPECT_TRUE(std::equal(f.sample(0), f.sample(1), all.sample(5)));
  const auto training = r.training_samples(std::vector<int>{2, 0});
  ASSERT_EQ(training.size(), records()[2].samples() + records()[0].samples());
  EXPECT_EQ(training.front().simulation, 2);
  EXPECT_EQ(training.back().simulation, 0);
  EXPECT_EQ(training.front().labels.shape(), (Shape{1, 2, 25, 25}));
  EXPECT_THROW((void)r.contacts(r.samples()), InvalidArgument);
  EXPECT_THROW((void)r.samples_of(std::vector<int>{3}), InvalidArgument);
}

TEST(DataSet, ResumeCutsAnInterruptedAppendAndContinuesToTheSameFile) {
  TempFile reference("reference.h5"), crashed("crashed.h5");
  write_all(reference.path, 3);
  write_all(crashed.path, 2);
  {  // a crash in the middle of appending simulation 2: some rows, /sims partly, no /sims/seed
    H5File f = H5File::open_rw(crashed.path);
    const auto& r = records()[2];
    f.append_rows<float>("/samples/features", std::span<const float>(r.features).subspan(0, 3 * 5 * 25 * 25));
    f.append_rows<double>("/contacts/gap", r.gap);
    f.append_rows<std::int32_t>("/sims/bodies", std::vector<std::int32_t>{r.bodies});
    f.append_rows<std::int64_t>("/sims/samples", std::vector<std::int64_t>{77});
  }
  {
    const DataSetReader r(crashed.path);  // readers see only committed simulations
    EXPECT_EQ(r.simulations().size(), 2u);
  }
  {
    DataSetWriter w = DataSetWriter::resume(crashed.path, small_params());
    EXPECT_EQ(w.completed_simulations(), 2);
    w.append(records()[2]);
    w.close();
  }
  const H5File a = H5File::open_read(reference.path), b = H5File::open_read(crashed.path);
  expect_same_datasets(a, b);
}

TEST(DataSet, ResumeRejectsOtherParametersAndOutOfOrderAppends) {
  TempFile tmp("params.h5");
  write_all(tmp.path, 1);
  DataSetParams other = small_params();
  other.seed = 12;
  try {
    (void)DataSetWriter::resume(tmp.path, other);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--seed"), std::string::npos) << e.what();
  }
  other = small_params();
  other.count_max = 15;
  EXPECT_THROW((void)DataSetWriter::resume(tmp.path, other), ConfigError);
  other = small_params();
  other.image.channels = {FeatureChannel::Mass};
  EXPECT_THROW((void)DataSetWriter::resume(tmp.path, other), ConfigError);
  DataSetWriter w = DataSetWriter::resume(tmp.path, small_params());
  EXPECT_THROW(w.append(records()[2]), InvalidArgument);
}

TEST(DataSet, ReaderRejectsWrongFormatVersionAndTruncation) {
  TempFile tmp("bad.h5");
  write_all(tmp.path, 2);
  EXPECT_NO_THROW(DataSetReader{tmp.path});
  {
    H5File f = H5File::open_rw(tmp.path);
    f.set_attribute<std::int32_t>("/", "format_version", 99);
  }
  EXPECT_THROW(DataSetReader{tmp.path}, IoError);
  write_all(tmp.path, 2);
  {
    H5File f = H5File::open_rw(tmp.path);
    f.set_attribute("/", "format", "deepcontact-trajectory");
  }
  EXPECT_THROW(DataSetReader{tmp.path}, IoError);
  write_all(tmp.path, 2);
  {  // rows missing that /sims says exist
    H5File f = H5File::open_rw(tmp.path);
    f.resize_rows("/samples/labels", 3);
  }
  EXPECT_THROW(DataSetReader{tmp.path}, IoError);
  write_all(tmp.path, 2);
  {
    H5File f = H5File::open_rw(tmp.path);
    f.remove("/contacts/point");
  }
  EXPECT_THROW(DataSetReader{tmp.path}, IoError);
  // Not HDF5 at all, and a file cut in half.
  write_all(tmp.path, 2);
  const auto size = fs::file_size(tmp.path);
  fs::resize_file(tmp.path, size / 2);
  EXPECT_THROW(DataSetReader{tmp.path}, IoError);
  { std::ofstream(tmp.path) << "not hdf5\n"; }
  EXPECT_THROW(DataSetReader{tmp.path}, IoError);
  EXPECT_THROW(DataSetReader{tmp.path + ".missing"}, IoError);
}

TEST(DataSet, BadParametersAreConfigErrors) {
  DataSetParams p = small_params();
  p.count_min = 20;
  p.count_max = 10;
  EXPECT_THROW(SimulationGenerator{p}, ConfigError);
  p = small_params();
  p.oracle.tolerance = 0;
  EXPECT_THROW(SimulationGenerator{p}, ConfigError);
  EXPECT_THROW((void)parse_oracle_kind("lemke"), ConfigError);
  EXPECT_EQ(parse_oracle_kind(to_string(OracleKind::Newton)), OracleKind::Newton);
  p = small_params();
  p.image = FeatureImageDef::for_box(30, 30);  // grid box ≠ scene box
  EXPECT_THROW(SimulationGenerator{p}, ConfigError);
}

}  // namespace
}  // namespace dc
