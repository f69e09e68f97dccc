// copy_h5_file (h5_copy.hpp): walks the source with HDF5's C API for what H5File does not
// expose (dataset creation properties, the stored type of an attribute, string kinds) and
// moves every value through H5File, so the copy gets this layer's layout and checksums.
#include "dc/io/h5_copy.hpp"

#include <cstdint>
#include <optional>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "h5_detail.hpp"

namespace dc {

using namespace h5_detail;

namespace {

/// What the copy needs to know about a source object that H5File does not say.
struct SourceInfo {
  const std::string& file;
  hid_t id;

  [[noreturn]] void fail(const std::string& object, const std::string& what) const {
    throw IoError(file + ": " + object + ": cannot copy: " + what);
  }

  /// Extendible (unlimited first axis) and gzip level of a dataset.
  H5DatasetOptions options(const std::string& path) const {
    const ErrorSilencer quiet;
    H5DatasetOptions o;
    Handle ds(H5Dopen2(id, path.c_str(), H5P_DEFAULT), H5Dclose);
    Handle space(H5Dget_space(ds.get()), H5Sclose);
    Handle dcpl(H5Dget_create_plist(ds.get()), H5Pclose);
    if (!ds.valid() || !space.valid() || !dcpl.valid()) fail(path, with_reason("cannot query the dataset"));
    const int rank = H5Sget_simple_extent_ndims(space.get());
    if (rank > 0) {
      std::vector<hsize_t> dims(static_cast<std::size_t>(rank)), maxdims(dims.size());
      H5Sget_simple_extent_dims(space.get(), dims.data(), maxdims.data());
      o.extendible = maxdims[0] == H5S_UNLIMITED;
    }
    const int filters = H5Pget_nfilters(dcpl.get());
    for (int i = 0; i < filters; ++i) {
      unsigned flags = 0, values[1] = {0};
      std::size_t n = 1;
      if (H5Pget_filter2(dcpl.get(), static_cast<unsigned>(i), &flags, &n, values, 0, nullptr, nullptr) ==
              H5Z_FILTER_DEFLATE && n >= 1)
        o.deflate = static_cast<int>(values[0]);
    }
    return o;
  }

  /// Variable or fixed-length strings of a dataset or (attribute != "") an attribute;
  /// nullopt when it does not hold strings. (The copy stores either kind fixed-length.)
  std::optional<H5StringKind> string_kind(const std::string& object, const std::string& attribute = {}) const {
    const ErrorSilencer quiet;
    Handle obj(attribute.empty() ? H5Dopen2(id, object.c_str(), H5P_DEFAULT)
                                 : H5Aopen_by_name(id, object.c_str(), attribute.c_str(), H5P_DEFAULT, H5P_DEFAULT),
               attribute.empty() ? H5Dclose : H5Aclose);
    if (!obj.valid()) fail(object, with_reason("cannot open " + (attribute.empty() ? "it" : "attribute " + attribute)));
    Handle type(attribute.empty() ? H5Dget_type(obj.get()) : H5Aget_type(obj.get()), H5Tclose);
    if (H5Tget_class(type.get()) != H5T_STRING) return std::nullopt;
    return H5Tis_variable_str(type.get()) > 0 ? H5StringKind::Variable : H5StringKind::Fixed;
  }

  /// Stored numeric type and element count of an attribute.
  std::pair<std::optional<H5Type>, hssize_t> attribute_type(const std::string& object, const std::string& name) const {
    const ErrorSilencer quiet;
    Handle a(H5Aopen_by_name(id, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    Handle type(H5Aget_type(a.get()), H5Tclose);
    Handle space(H5Aget_space(a.get()), H5Sclose);
    if (!a.valid() || !type.valid() || !space.valid()) fail(object, with_reason("cannot open attribute " + name));
    const bool scalar = H5Sget_simple_extent_type(space.get()) == H5S_SCALAR;
    return {classify(type.get()), scalar ? -1 : H5Sget_simple_extent_npoints(space.get())};
  }
};

template <H5Element T>
void copy_attribute_values(const H5File& in, H5File& out, const std::string& object, const std::string& name,
                           bool scalar) {
  if (scalar) out.set_attribute<T>(object, name, in.attribute<T>(object, name));
  else out.set_attribute_array<T>(object, name, in.attribute_array<T>(object, name));
}

void copy_attributes(const SourceInfo& src, const H5File& in, H5File& out, const std::string& object) {
  for (const std::string& name : in.attribute_names(object)) {
    if (const auto kind = src.string_kind(object, name)) {
      out.set_attribute(object, name, in.attribute_string(object, name));  // fixed-length: see H5StringKind
      continue;
    }
    const auto [type, count] = src.attribute_type(object, name);
    if (!type) src.fail(object, "attribute " + name + " has a type this layer does not handle");
    const bool scalar = count < 0;
    switch (*type) {
      case H5Type::Float64: copy_attribute_values<double>(in, out, object, name, scalar); break;
      case H5Type::Float32: copy_attribute_values<float>(in, out, object, name, scalar); break;
      case H5Type::Int32: copy_attribute_values<std::int32_t>(in, out, object, name, scalar); break;
      case H5Type::Int64: copy_attribute_values<std::int64_t>(in, out, object, name, scalar); break;
      case H5Type::UInt8: copy_attribute_values<std::uint8_t>(in, out, object, name, scalar); break;
    }
  }
}

template <H5Element T>
void copy_values(const H5File& in, H5File& out, const std::string& path, const H5DatasetOptions& o) {
  out.write<T>(path, in.read<T>(path), in.shape(path), o);
}

void copy_dataset(const SourceInfo& src, const H5File& in, H5File& out, const std::string& path) {
  if (const auto kind = src.string_kind(path)) {
    if (in.shape(path).size() != 1) src.fail(path, "only 1-D string datasets are handled");
    out.write_strings(path, in.read_strings(path));  // fixed-length: see H5StringKind
    return;
  }
  const H5DatasetOptions o = src.options(path);
  switch (in.type(path)) {
    case H5Type::Float64: copy_values<double>(in, out, path, o); break;
    case H5Type::Float32: copy_values<float>(in, out, path, o); break;
    case H5Type::Int32: copy_values<std::int32_t>(in, out, path, o); break;
    case H5Type::Int64: copy_values<std::int64_t>(in, out, path, o); break;
    case H5Type::UInt8: copy_values<std::uint8_t>(in, out, path, o); break;
  }
}

void copy_group(const SourceInfo& src, const H5File& in, H5File& out, const std::string& group) {
  if (group != "/") out.create_group(group);
  copy_attributes(src, in, out, group);
  for (const std::string& child : in.children(group)) {
    const std::string path = (group == "/" ? "/" : group + "/") + child;
    in.require_in_file(path);  // a copy would turn a missing source into checksummed zeros
    if (in.is_group(path)) {
      copy_group(src, in, out, path);
    } else if (in.is_dataset(path)) {
      copy_dataset(src, in, out, path);
      copy_attributes(src, in, out, path);
    } else {
      src.fail(path, "neither a group nor a dataset");
    }
  }
}

}  // namespace

void copy_h5_file(const std::string& from, const std::string& to) {
  const H5File in = H5File::open_read(from);
  const ErrorSilencer quiet;
  Handle raw(H5Fopen(from.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!raw.valid()) throw IoError(from + ": " + with_reason("cannot open HDF5 file"));
  const SourceInfo src{from, raw.get()};
  AtomicH5File out(to);
  copy_group(src, in, out.file(), "/");
  out.commit();
}

}  // namespace dc
