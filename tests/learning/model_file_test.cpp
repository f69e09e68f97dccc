// Model files: save → load reproduces outputs bit for bit; damaged, truncated, foreign
// and other-version files throw dc::IoError with a one-line message.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "dc/learning/initializer.hpp"
#include "dc/learning/model_file.hpp"
#include "grad_check.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

class ModelFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dc_model_file_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static Model make_model() {
    ModelGrid g;
    g.image.sph.grid.spacing = 0.25;
    g.image.sph.grid.width = 3.5;  // 15 x 13 nodes
    g.image.sph.grid.height = 3.0;
    g.image.sph.support = 0.25;
    g.image.sph.kernel = SphKernelType::Spiky;
    g.image.channels = {FeatureChannel::Mass, FeatureChannel::Vx, FeatureChannel::Vy, FeatureChannel::Omega,
                        FeatureChannel::Nx};
    Model m(default_arch(), g, 5);
    Rng rng(5);
    m.network().initialize(HeNormal(), rng);
    for (ParamRef& p : m.network().parameters())
      if (!p.decay) test::fill_gaussian(*p.value, rng, 0.1);
    m.input_stats = {{1, 2, 3, 4, 5}, {0.5f, 1, 2, 3, 4}};
    m.output_stats = {{-1, 1}, {2, 3}};
    return m;
  }

  void expect_io_error(const fs::path& p, const std::string& needle) {
    try {
      (void)load_model(p);
      ADD_FAILURE() << "no IoError for " << p;
    } catch (const IoError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(needle), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }

  fs::path dir_;
};

TEST_F(ModelFile, SaveLoadGivesIdenticalOutputs) {
  Model a = make_model();
  const fs::path p = dir_ / "m.h5";
  save_model(a, p);
  EXPECT_TRUE(fs::exists(p));
  EXPECT_FALSE(fs::exists(dir_ / "m.h5.tmp"));
  Model b = load_model(p);
  EXPECT_EQ(b.network().arch().to_toml(), a.network().arch().to_toml());
  EXPECT_EQ(b.grid().image.sph.kernel, SphKernelType::Spiky);
  EXPECT_EQ(b.grid().image.sph.grid.spacing, 0.25);
  EXPECT_EQ(b.grid().image.sph.support, 0.25);
  EXPECT_EQ(b.grid().nx(), 15);
  EXPECT_EQ(b.grid().ny(), 13);
  EXPECT_EQ(b.grid().image.channels, a.grid().image.channels);
  EXPECT_EQ(b.grid().label_channels, a.grid().label_channels);
  EXPECT_EQ(b.input_stats.std, a.input_stats.std);
  EXPECT_EQ(b.output_stats.mean, a.output_stats.mean);
  Tensor x(3, 5, 13, 15);
  Rng rng(6);
  test::fill_gaussian(x, rng);
  const Tensor ya = a.predict(x), yb = b.predict(x);
  ASSERT_EQ(ya.shape(), (Shape{3, 2, 13, 15}));
  EXPECT_EQ(std::memcmp(ya.data(), yb.data(), sizeof(float) * ya.size()), 0);
  // Overwriting an existing file works (rename onto it).
  save_model(b, p);
  EXPECT_NO_THROW((void)load_model(p));
}

// label_scale: stored and reloaded; predict() returns s·sinh of the scale-0 model's output,
// and compress_labels inverts expand_labels.
TEST_F(ModelFile, LabelScaleIsStoredAndPredictExpandsTheOutput) {
  Model plain = make_model();
  Model scaled = make_model();
  ModelGrid g = scaled.grid();
  g.labels.scale = 7.5;
  g.labels.deadzone = 2.5;
  Model withscale(scaled.network().arch(), g, 5);
  const auto src = scaled.network().parameters(), dst = withscale.network().parameters();
  for (std::size_t i = 0; i < src.size(); ++i) *dst[i].value = *src[i].value;
  withscale.input_stats = scaled.input_stats;
  withscale.output_stats = scaled.output_stats;
  const fs::path p = dir_ / "s.h5";
  save_model(withscale, p);
  Model back = load_model(p);
  EXPECT_EQ(back.grid().labels.scale, 7.5);
  EXPECT_EQ(back.grid().labels.deadzone, 2.5);
  EXPECT_EQ(back.grid().labels.kind, LabelKind::Absolute);
  Tensor x(2, 5, 13, 15);
  Rng rng(9);
  test::fill_gaussian(x, rng);
  const Tensor y0 = plain.predict(x), ys = back.predict(x);
  ASSERT_EQ(y0.size(), ys.size());
  for (std::size_t i = 0; i < y0.size(); ++i)
    ASSERT_NEAR(ys[i], 7.5f * std::sinh(y0[i]), 1e-4f * (1 + std::abs(ys[i]))) << i;
  Tensor t = ys;
  compress_labels(t, 7.5);
  for (std::size_t i = 0; i < y0.size(); ++i) ASSERT_NEAR(t[i], y0[i], 1e-4f * (1 + std::abs(y0[i]))) << i;
  ModelGrid bad = g;
  bad.labels.scale = -1;
  EXPECT_THROW(Model(scaled.network().arch(), bad, 5), ConfigError);
}

TEST_F(ModelFile, DamagedFilesThrowIoError) {
  Model a = make_model();
  const fs::path good = dir_ / "good.h5";
  save_model(a, good);
  auto copy = [&](const std::string& name) {
    const fs::path p = dir_ / name;
    fs::copy_file(good, p, fs::copy_options::overwrite_existing);
    return p;
  };
  {
    const fs::path p = copy("version.h5");
    H5File::open_rw(p.string()).set_attribute<std::int32_t>("/", "format_version", kModelFormatVersion + 1);
    expect_io_error(p, "version " + std::to_string(kModelFormatVersion + 1));
  }
  {
    const fs::path p = copy("version0.h5");
    H5File::open_rw(p.string()).set_attribute<std::int32_t>("/", "format_version", 0);
    expect_io_error(p, "version 0");
  }
  {
    const fs::path p = copy("nokind.h5");  // version 2 requires label_kind
    H5File::open_rw(p.string()).remove_attribute("/grid", "label_kind");
    expect_io_error(p, "label_kind");
  }
  {
    const fs::path p = copy("nodeadzone.h5");
    H5File::open_rw(p.string()).remove_attribute("/grid", "correction_deadzone");
    expect_io_error(p, "correction_deadzone");
  }
  {
    const fs::path p = copy("noscale.h5");
    H5File::open_rw(p.string()).remove_attribute("/grid", "label_scale");
    expect_io_error(p, "label_scale");
  }
  {
    const fs::path p = copy("badkind.h5");
    H5File::open_rw(p.string()).set_attribute("/grid", "label_kind", std::string("relative"));
    expect_io_error(p, "relative");
  }
  {
    // A version-1 file has no label_kind: it still loads, as an absolute model.
    const fs::path p = copy("v1.h5");
    {
      H5File f = H5File::open_rw(p.string());
      f.set_attribute<std::int32_t>("/", "format_version", 1);
      f.remove_attribute("/grid", "label_kind");
      f.remove_attribute("/grid", "label_scale");
      f.remove_attribute("/grid", "correction_deadzone");
    }
    EXPECT_EQ(load_model(p).grid().labels.kind, LabelKind::Absolute);
  }
  {
    // Stored names become types on load: an unknown channel or kernel is a one-line IoError.
    const fs::path p = copy("badchannel.h5");
    {
      H5File f = H5File::open_rw(p.string());
      f.remove("/grid/feature_channels");
      f.write_strings("/grid/feature_channels", {"mass", "vx", "vy", "omega", "speed"});
    }
    expect_io_error(p, "speed");
  }
  {
    const fs::path p = copy("badkernel.h5");
    H5File::open_rw(p.string()).set_attribute("/grid", "kernel", std::string("gauss"));
    expect_io_error(p, "gauss");
  }
  {
    const fs::path p = copy("missing.h5");
    H5File::open_rw(p.string()).remove("/weights/d2/weight");
    expect_io_error(p, "/weights/d2/weight");
  }
  {
    const fs::path p = copy("shape.h5");
    H5File f = H5File::open_rw(p.string());
    f.remove("/weights/e1/bias");
    f.write<float>("/weights/e1/bias", std::vector<float>(15, 0.0f), {1, 15, 1, 1});
    f.close();
    expect_io_error(p, "/weights/e1/bias");
  }
  {
    const fs::path p = copy("arch.h5");
    H5File f = H5File::open_rw(p.string());
    f.remove("/arch");
    f.write_strings("/arch", {"[[layer]]\ntype = \"pool\"\n"});
    f.close();
    expect_io_error(p, "unknown layer type");
  }
  {
    const fs::path p = dir_ / "text.h5";
    std::ofstream(p) << "this is not an HDF5 file\n";
    expect_io_error(p, p.filename().string());
  }
  {
    const fs::path p = dir_ / "truncated.h5";
    std::ifstream in(good, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(p, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
    expect_io_error(p, p.filename().string());
  }
  expect_io_error(dir_ / "does-not-exist.h5", "does-not-exist.h5");
}

}  // namespace
}  // namespace dc
