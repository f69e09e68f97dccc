#include "dc/learning/model_file.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"

namespace dc {

namespace {

constexpr const char* kFormat = "deepcontact-cnn-model";

H5Shape shape_of(const Tensor& t) {
  return {static_cast<hsize_t>(t.n()), static_cast<hsize_t>(t.c()), static_cast<hsize_t>(t.h()),
          static_cast<hsize_t>(t.w())};
}

std::vector<std::int32_t> chw(const Shape& s) { return {s.c, s.h, s.w}; }

}  // namespace

void save_model(Model& model, const std::filesystem::path& path) { save_model(model, path, {}); }

void save_model(Model& model, const std::filesystem::path& path, const std::function<void(H5File&)>& extra) {
  AtomicH5File out(path.string());
  H5File& f = out.file();
  Network& net = model.network();
  f.set_attribute("/", "format", kFormat);
  f.set_attribute<std::int32_t>("/", "format_version", kModelFormatVersion);
  const auto in = chw(net.input_shape()), outs = chw(net.output_shape());
  f.set_attribute_array<std::int32_t>("/", "input_shape", in);
  f.set_attribute_array<std::int32_t>("/", "output_shape", outs);
  f.write_strings("/arch", {net.arch().to_toml()});
  for (const ParamRef& p : net.parameters())
    f.write<float>("/weights/" + p.name, std::span<const float>(p.value->data(), p.value->size()), shape_of(*p.value));
  auto vec = [&](const char* name, const std::vector<float>& v) {
    f.write<float>(std::string("/normalisation/") + name, v, {static_cast<hsize_t>(v.size())});
  };
  vec("input_mean", model.input_stats.mean);
  vec("input_std", model.input_stats.std);
  vec("output_mean", model.output_stats.mean);
  vec("output_std", model.output_stats.std);
  const ModelGrid& g = model.grid();
  f.create_group("/grid");
  f.set_attribute<double>("/grid", "d", g.image.sph.grid.spacing);
  f.set_attribute<double>("/grid", "h", g.image.sph.support);
  f.set_attribute("/grid", "kernel", to_string(g.image.sph.kernel));
  f.set_attribute<std::int32_t>("/grid", "nx", g.nx());
  f.set_attribute<std::int32_t>("/grid", "ny", g.ny());
  f.set_attribute("/grid", "label_kind", to_string(g.labels.kind));
  f.set_attribute<double>("/grid", "label_scale", g.labels.scale);
  f.set_attribute<double>("/grid", "correction_deadzone", g.labels.deadzone);
  f.write_strings("/grid/feature_channels", feature_channel_names(g.image.channels));
  f.write_strings("/grid/label_channels", g.label_channels);
  if (extra) extra(f);
  out.commit();
}

Model load_model(const std::filesystem::path& path) {
  const std::string file = path.string();
  const H5File f = H5File::open_read(file);  // missing / non-HDF5 / truncated → IoError
  if (!f.has_attribute("/", "format_version"))
    throw IoError(file + ": not a DeepContact model file (no format_version attribute)");
  const auto version = f.attribute<std::int32_t>("/", "format_version");
  if (version < kModelFormatVersionOldest || version > kModelFormatVersion)
    throw IoError(file + ": model format version " + std::to_string(version) + ", this build reads versions " +
                  std::to_string(kModelFormatVersionOldest) + " to " + std::to_string(kModelFormatVersion));
  const auto in = f.attribute_array<std::int32_t>("/", "input_shape");
  if (in.size() != 3) throw IoError(file + ": attribute input_shape must have 3 entries (C, H, W)");
  const auto arch_text = f.read_strings("/arch");
  if (arch_text.size() != 1) throw IoError(file + ": /arch must hold one string");
  ArchSpec arch;
  try {
    arch = ArchSpec::parse(arch_text[0], file + ":/arch");
  } catch (const ConfigError& e) {
    throw IoError(std::string(e.what()));
  }
  // Stored texts become types here; an unknown kernel, channel or label kind is an IoError
  // naming the file and the object.
  const auto parsed = [&](const char* where, const auto& parse) {
    try {
      return parse();
    } catch (const ConfigError& e) {
      throw IoError(file + ": " + where + ": " + e.what());
    }
  };
  const double d = f.attribute<double>("/grid", "d");
  const int nx = f.attribute<std::int32_t>("/grid", "nx"), ny = f.attribute<std::int32_t>("/grid", "ny");
  if (!(d > 0) || !std::isfinite(d) || nx < 1 || ny < 1)
    throw IoError(file + ": /grid: d must be a finite number > 0 and nx, ny >= 1");
  ModelGrid g;
  // The file stores node counts, not the box: (n − 1)·d gives n nodes (sph_node_count).
  g.image.sph.grid.width = (nx - 1) * d;
  g.image.sph.grid.height = (ny - 1) * d;
  g.image.sph.grid.spacing = d;
  g.image.sph.support = f.attribute<double>("/grid", "h");
  g.image.sph.kernel = parsed("/grid kernel", [&] { return parse_sph_kernel(f.attribute_string("/grid", "kernel")); });
  g.image.channels.clear();
  for (const std::string& name : f.read_strings("/grid/feature_channels"))
    g.image.channels.push_back(parsed("/grid/feature_channels", [&] { return parse_feature_channel(name); }));
  g.label_channels = f.read_strings("/grid/label_channels");
  if (version >= 2) {
    if (!f.has_attribute("/grid", "label_kind")) throw IoError(file + ": /grid has no label_kind attribute");
    g.labels.kind = parsed("/grid label_kind", [&] { return parse_label_kind(f.attribute_string("/grid", "label_kind")); });
    if (!f.has_attribute("/grid", "label_scale")) throw IoError(file + ": /grid has no label_scale attribute");
    g.labels.scale = f.attribute<double>("/grid", "label_scale");
    if (!f.has_attribute("/grid", "correction_deadzone"))
      throw IoError(file + ": /grid has no correction_deadzone attribute");
    g.labels.deadzone = f.attribute<double>("/grid", "correction_deadzone");
  }
  if (g.nx() != nx || g.ny() != ny)
    throw IoError(file + ": /grid: nx, ny do not fit the spacing d");
  if (in[1] != g.ny() || in[2] != g.nx())
    throw IoError(file + ": input_shape " + std::to_string(in[1]) + "x" + std::to_string(in[2]) +
                  " does not match the grid " + std::to_string(g.ny()) + "x" + std::to_string(g.nx()));
  auto build = [&]() {
    try {
      return Model(std::move(arch), g, in[0]);
    } catch (const std::exception& e) {  // ConfigError / InvalidArgument from the arch or names
      throw IoError(file + ": " + e.what());
    }
  };
  Model model = build();
  Network& net = model.network();
  const auto outs = f.attribute_array<std::int32_t>("/", "output_shape");
  if (outs != chw(net.output_shape()))
    throw IoError(file + ": output_shape attribute does not match the architecture's output");
  for (const ParamRef& p : net.parameters()) {
    const std::vector<float> v = f.read<float>("/weights/" + p.name, shape_of(*p.value));
    std::memcpy(p.value->data(), v.data(), sizeof(float) * v.size());
  }
  auto vec = [&](const char* name, int channels) {
    return f.read<float>(std::string("/normalisation/") + name, {static_cast<hsize_t>(channels)});
  };
  const int cin = net.input_shape().c, cout = net.output_shape().c;
  model.input_stats = {vec("input_mean", cin), vec("input_std", cin)};
  model.output_stats = {vec("output_mean", cout), vec("output_std", cout)};
  for (const auto* s : {&model.input_stats, &model.output_stats})
    for (float sd : s->std)
      if (!(sd > 0.0f)) throw IoError(file + ": normalisation std must be positive");
  return model;
}

}  // namespace dc
