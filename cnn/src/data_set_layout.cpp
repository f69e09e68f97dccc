#include "data_set_layout.hpp"

#include <sstream>

#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"

namespace dc::dataset {

namespace {

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ",") + s;
  return out;
}

std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

template <class T>
void extendible(H5File& f, const char* path, H5Shape row_shape, hsize_t chunk_rows = 0, int deflate = 0) {
  row_shape.insert(row_shape.begin(), 0);
  f.create_dataset<T>(path, row_shape, {.extendible = true, .chunk_rows = chunk_rows, .deflate = deflate});
}

}  // namespace

void write_params(H5File& f, const DataSetParams& p) {
  SphGrid grid(p.image.sph.grid);  // node counts exactly as the builder computes them
  f.set_attribute("/", "format", kDataSetFormat);
  f.set_attribute<std::int32_t>("/", "format_version", kDataSetFormatVersion);
  f.set_attribute("/", "scene", scene_to_toml(p.scene));
  f.set_attribute<std::int64_t>("/", "seed", static_cast<std::int64_t>(p.seed));
  f.set_attribute<std::int32_t>("/", "count_min", p.count_min);
  f.set_attribute<std::int32_t>("/", "count_max", p.count_max);
  f.set_attribute<std::int32_t>("/", "steps", p.scene.time.steps);
  f.set_attribute<double>("/", "grid_width", p.image.sph.grid.width);
  f.set_attribute<double>("/", "grid_height", p.image.sph.grid.height);
  f.set_attribute<double>("/", "grid_spacing", p.image.sph.grid.spacing);
  f.set_attribute<double>("/", "grid_support", p.image.sph.support);
  f.set_attribute("/", "grid_kernel", to_string(p.image.sph.kernel));
  f.set_attribute<std::int32_t>("/", "grid_nx", grid.nx());
  f.set_attribute<std::int32_t>("/", "grid_ny", grid.ny());
  f.set_attribute("/", "feature_channels", join(feature_channel_names(p.image.channels)));
  f.set_attribute("/", "label_channels", join(label_channel_names()));
  f.set_attribute("/", "label_kind", "shepard-numerator");
  f.set_attribute("/", "oracle", p.oracle.describe());
  f.set_attribute("/", "oracle_method", to_string(p.oracle.method));
  f.set_attribute<double>("/", "oracle_tolerance", p.oracle.tolerance);
  f.set_attribute<std::int32_t>("/", "oracle_sweeps", p.oracle.sweeps);
}

DataSetParams read_params(const H5File& f) {
  const std::string& path = f.path();
  const auto bad = [&](const std::string& what) { return IoError(path + ": " + what); };
  if (!f.has_attribute("/", "format") || f.attribute_string("/", "format") != kDataSetFormat)
    throw bad(std::string("not a DeepContact data set (root attribute format != '") + kDataSetFormat + "')");
  if (!f.has_attribute("/", "format_version"))
    throw bad("missing root attribute format_version");
  const auto version = f.attribute<std::int32_t>("/", "format_version");
  if (version != kDataSetFormatVersion && version != kShardedFormatVersion)
    throw bad("data set format_version " + std::to_string(version) + " is not supported (this build reads " +
              std::to_string(kDataSetFormatVersion) + " and " + std::to_string(kShardedFormatVersion) + ")");
  for (const char* a : {"scene", "seed", "count_min", "count_max", "steps", "grid_width", "grid_height",
                        "grid_spacing", "grid_support", "grid_kernel", "grid_nx", "grid_ny", "feature_channels",
                        "label_channels", "oracle_method", "oracle_tolerance", "oracle_sweeps"})
    if (!f.has_attribute("/", a)) throw bad(std::string("missing root attribute ") + a);
  DataSetParams p;
  try {
    p.scene = parse_scene(f.attribute_string("/", "scene"), path + ": attribute scene");
    p.seed = static_cast<std::uint64_t>(f.attribute<std::int64_t>("/", "seed"));
    p.count_min = f.attribute<std::int32_t>("/", "count_min");
    p.count_max = f.attribute<std::int32_t>("/", "count_max");
    p.image.sph.grid.width = f.attribute<double>("/", "grid_width");
    p.image.sph.grid.height = f.attribute<double>("/", "grid_height");
    p.image.sph.grid.spacing = f.attribute<double>("/", "grid_spacing");
    p.image.sph.support = f.attribute<double>("/", "grid_support");
    p.image.sph.kernel = parse_sph_kernel(f.attribute_string("/", "grid_kernel"));
    p.image.sph.grid.channels = FeatureImageBuilder::kLabelChannels;
    p.image.sph.normalisation = SphNormalisation::Shepard;
    p.image.channels = parse_feature_channels(f.attribute_string("/", "feature_channels"));
    p.oracle.method = parse_oracle_kind(f.attribute_string("/", "oracle_method"));
    p.oracle.tolerance = f.attribute<double>("/", "oracle_tolerance");
    p.oracle.sweeps = f.attribute<std::int32_t>("/", "oracle_sweeps");
    p.validate();
  } catch (const IoError&) {
    throw;
  } catch (const std::exception& e) {
    throw bad(std::string("bad data set attributes: ") + e.what());
  }
  if (f.attribute<std::int32_t>("/", "steps") != p.scene.time.steps)
    throw bad("attribute steps disagrees with the scene's [time] steps");
  if (f.attribute_string("/", "label_channels") != join(label_channel_names()))
    throw bad("unsupported label_channels '" + f.attribute_string("/", "label_channels") + "'");
  SphGrid grid(p.image.sph.grid);
  if (f.attribute<std::int32_t>("/", "grid_nx") != grid.nx() || f.attribute<std::int32_t>("/", "grid_ny") != grid.ny())
    throw bad("attributes grid_nx/grid_ny disagree with grid_width/grid_height/grid_spacing");
  return p;
}

std::string first_difference(const DataSetParams& a, const DataSetParams& b) {
  if (a.seed != b.seed) return "--seed (file " + std::to_string(a.seed) + ", requested " + std::to_string(b.seed) + ")";
  if (a.count_min != b.count_min || a.count_max != b.count_max)
    return "--count (file " + std::to_string(a.count_min) + ".." + std::to_string(a.count_max) + ", requested " +
           std::to_string(b.count_min) + ".." + std::to_string(b.count_max) + ")";
  if (a.scene.time.steps != b.scene.time.steps)
    return "--steps (file " + std::to_string(a.scene.time.steps) + ", requested " +
           std::to_string(b.scene.time.steps) + ")";
  if (scene_to_toml(a.scene) != scene_to_toml(b.scene)) return "the scene (--scene/--set)";
  const auto& ga = a.image.sph;
  const auto& gb = b.image.sph;
  if (ga.kernel != gb.kernel || ga.support != gb.support || ga.grid.spacing != gb.grid.spacing ||
      ga.grid.width != gb.grid.width || ga.grid.height != gb.grid.height)
    return std::string("--grid (file ") + to_string(ga.kernel) + ":" + num(ga.grid.spacing) + ":" + num(ga.support) +
           ", requested " + to_string(gb.kernel) + ":" + num(gb.grid.spacing) + ":" + num(gb.support) + ")";
  if (a.image.channels != b.image.channels)
    return "--channels (file " + join(feature_channel_names(a.image.channels)) + ", requested " +
           join(feature_channel_names(b.image.channels)) + ")";
  if (a.oracle.describe() != b.oracle.describe())
    return "--oracle (file '" + a.oracle.describe() + "', requested '" + b.oracle.describe() + "')";
  return "";
}

void create_layout(H5File& f, const DataSetParams& p) {
  SphGrid grid(p.image.sph.grid);
  const auto ny = static_cast<hsize_t>(grid.ny()), nx = static_cast<hsize_t>(grid.nx());
  const auto cf = static_cast<hsize_t>(p.image.channels.size());
  extendible<std::int32_t>(f, "/samples/sim", {}, kIndexChunkRows);
  extendible<std::int32_t>(f, "/samples/step", {}, kIndexChunkRows);
  extendible<float>(f, kFeatures, {cf, ny, nx}, kImageChunkRows, kDeflate);
  extendible<float>(f, kLabels, {FeatureImageBuilder::kLabelChannels, ny, nx}, kImageChunkRows, kDeflate);
  extendible<std::int64_t>(f, "/samples/body_begin", {}, kIndexChunkRows);
  extendible<std::int32_t>(f, "/samples/body_count", {}, kIndexChunkRows);
  extendible<std::int64_t>(f, "/samples/contact_begin", {}, kIndexChunkRows);
  extendible<std::int32_t>(f, "/samples/contact_count", {}, kIndexChunkRows);
  extendible<double>(f, "/samples/residual", {}, kIndexChunkRows);
  extendible<double>(f, "/bodies/position", {2}, 0, kDeflate);
  extendible<double>(f, "/bodies/velocity", {2}, 0, kDeflate);
  extendible<double>(f, "/bodies/omega", {}, 0, kDeflate);
  extendible<double>(f, "/bodies/angle", {}, 0, kDeflate);
  extendible<double>(f, "/bodies/radius", {}, 0, kDeflate);
  extendible<double>(f, "/bodies/mass", {}, 0, kDeflate);
  extendible<std::int32_t>(f, "/contacts/body_a", {}, 0, kDeflate);
  extendible<std::int32_t>(f, "/contacts/body_b", {}, 0, kDeflate);
  extendible<double>(f, "/contacts/point", {2}, 0, kDeflate);
  extendible<double>(f, "/contacts/normal", {2}, 0, kDeflate);
  extendible<double>(f, "/contacts/gap", {}, 0, kDeflate);
  extendible<double>(f, "/contacts/lambda_star", {2}, 0, kDeflate);
  extendible<std::int32_t>(f, kSimsBodies, {}, kSimsChunkRows);
  extendible<std::int64_t>(f, kSimsSamples, {}, kSimsChunkRows);
  extendible<std::int64_t>(f, kSimsContacts, {}, kSimsChunkRows);
  extendible<double>(f, kSimsResidual, {}, kSimsChunkRows);
  extendible<std::int64_t>(f, kSimsSeed, {}, kSimsChunkRows);
}

RowCounts committed_rows(const H5File& f) {
  RowCounts r;
  for (const char* p : {kSimsSeed, kSimsBodies, kSimsSamples, kSimsContacts, kSimsResidual})
    if (!f.is_dataset(p)) throw IoError(f.path() + ": " + p + ": missing (truncated or not a data set)");
  const hsize_t k = f.rows(kSimsSeed);
  for (const char* p : {kSimsBodies, kSimsSamples, kSimsContacts, kSimsResidual})
    if (f.rows(p) < k)
      throw IoError(f.path() + ": " + p + ": " + std::to_string(f.rows(p)) + " rows but /sims/seed has " +
                    std::to_string(k) + " (corrupt data set)");
  r.completed = static_cast<int>(k);
  if (k == 0) return r;
  const auto bodies = f.read_rows<std::int32_t>(kSimsBodies, 0, k);
  const auto samples = f.read_rows<std::int64_t>(kSimsSamples, 0, k);
  const auto contacts = f.read_rows<std::int64_t>(kSimsContacts, 0, k);
  for (hsize_t i = 0; i < k; ++i) {
    if (bodies[i] < 0 || samples[i] < 0 || contacts[i] < 0)
      throw IoError(f.path() + ": /sims: negative count in row " + std::to_string(i));
    // A damaged /sims row can claim any count: sum with overflow checks (fuzz_dataset
    // found int64 overflow here), so a corrupt file is an IoError, never undefined behaviour.
    std::int64_t body_rows = 0;
    if (__builtin_mul_overflow(static_cast<std::int64_t>(bodies[i]), samples[i], &body_rows) ||
        __builtin_add_overflow(r.samples, samples[i], &r.samples) ||
        __builtin_add_overflow(r.body_rows, body_rows, &r.body_rows) ||
        __builtin_add_overflow(r.contact_rows, contacts[i], &r.contact_rows))
      throw IoError(f.path() + ": /sims: counts in row " + std::to_string(i) + " overflow (corrupt data set)");
  }
  // Σ bodies × samples is exact when every sample of a simulation has its B bodies; when
  // bodies enter during a run (inflow) B is the final count and a sample has its own
  // /samples/body_count: the last committed sample's rows end where the body rows end.
  const auto last = static_cast<hsize_t>(r.samples);
  if (last > 0 && f.is_dataset("/samples/body_begin") && f.is_dataset("/samples/body_count") &&
      f.rows("/samples/body_begin") >= last && f.rows("/samples/body_count") >= last) {
    const auto b = f.read_rows<std::int64_t>("/samples/body_begin", last - 1, 1);
    const auto c = f.read_rows<std::int32_t>("/samples/body_count", last - 1, 1);
    std::int64_t end = 0;
    if (!b.empty() && !c.empty() && b[0] >= 0 && c[0] >= 0 && !__builtin_add_overflow(b[0], c[0], &end) &&
        end <= r.body_rows)
      r.body_rows = end;
  }
  return r;
}

}  // namespace dc::dataset
