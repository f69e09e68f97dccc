// HDF5 layer: attributes on "/" (the file), groups and datasets (see h5.hpp).
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "h5_detail.hpp"

namespace dc {

using namespace h5_detail;

// ---- attributes ---------------------------------------------------------------------------

namespace {
std::string attr_label(std::string_view name) {
  return "attribute '" + std::string(name) + "'";
}
}  // namespace

bool H5File::has_attribute(std::string_view object, std::string_view name) const {
  require_open();
  const ErrorSilencer quiet;
  Handle obj(H5Oopen(id_, object_name(object).c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.valid()) fail(object, "cannot open object to query " + attr_label(name));
  const htri_t ok = H5Aexists(obj.get(), std::string(name).c_str());
  if (ok < 0) fail(object, "cannot query " + attr_label(name));
  return ok > 0;
}

namespace {
/// Opens `object` and deletes an attribute `name` if present, so it can be re-created with
/// a possibly different type or shape (HDF5 cannot change those in place).
/// A string attribute's stored checksum goes with it (a stale one would fail the next read).
Handle open_for_new_attribute(hid_t file, const std::string& object, const std::string& name) {
  Handle obj(H5Oopen(file, object.c_str(), H5P_DEFAULT), H5Oclose);
  if (obj.valid() && H5Aexists(obj.get(), name.c_str()) > 0) H5Adelete(obj.get(), name.c_str());
  const std::string checksum = attribute_checksum_name(name);
  if (obj.valid() && H5Aexists(obj.get(), checksum.c_str()) > 0) H5Adelete(obj.get(), checksum.c_str());
  return obj;
}
}  // namespace

void H5File::set_attribute(std::string_view object, std::string_view name, std::string_view value, H5StringKind kind) {
  require_writable(object);
  const ErrorSilencer quiet;
  const std::string n(name);
  const Handle obj = open_for_new_attribute(id_, object_name(object), n);
  if (!obj.valid()) fail(object, "cannot open object to set " + attr_label(name));
  const Handle type = string_type(kind, value.size());
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj.get(), n.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) fail(object, "cannot create " + attr_label(name));
  const std::string copy(value);  // NUL-terminated
  herr_t rc;
  if (kind == H5StringKind::Variable) {
    const char* p = copy.c_str();
    rc = H5Awrite(attr.get(), type.get(), &p);
  } else {
    std::string padded = copy;
    padded.resize(std::max<std::size_t>(copy.size(), 1), '\0');
    rc = H5Awrite(attr.get(), type.get(), padded.data());
  }
  if (rc < 0) fail(object, "cannot write " + attr_label(name));
  // A variable-length string's bytes live in the global heap, which HDF5 does not checksum;
  // a fixed-length one is inside the (checksummed) object header.
  if (kind == H5StringKind::Variable)
    set_attribute<std::int64_t>(object, attribute_checksum_name(name), strings_checksum({copy}));
}

template <H5Element T>
void H5File::set_attribute(std::string_view object, std::string_view name, T value) {
  require_writable(object);
  const ErrorSilencer quiet;
  const std::string n(name);
  const Handle obj = open_for_new_attribute(id_, object_name(object), n);
  if (!obj.valid()) fail(object, "cannot open object to set " + attr_label(name));
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj.get(), n.c_str(), file_type(type_of<T>()), space.get(), H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose);
  if (!attr.valid() || H5Awrite(attr.get(), memory_type(type_of<T>()), &value) < 0)
    fail(object, "cannot write " + attr_label(name));
}

template <H5Element T>
void H5File::set_attribute_array(std::string_view object, std::string_view name, std::span<const T> values) {
  require_writable(object);
  const ErrorSilencer quiet;
  const std::string n(name);
  const Handle obj = open_for_new_attribute(id_, object_name(object), n);
  if (!obj.valid()) fail(object, "cannot open object to set " + attr_label(name));
  const hsize_t size = values.size();
  Handle space(H5Screate_simple(1, &size, nullptr), H5Sclose);
  Handle attr(H5Acreate2(obj.get(), n.c_str(), file_type(type_of<T>()), space.get(), H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose);
  if (!attr.valid() || (size > 0 && H5Awrite(attr.get(), memory_type(type_of<T>()), values.data()) < 0))
    fail(object, "cannot write " + attr_label(name));
}

namespace {

/// An open attribute with its type, dataspace and number of elements; `error` says what
/// failed when `attr` is invalid.
struct OpenAttribute {
  Handle attr;
  Handle type;
  Handle space;
  hsize_t count = 0;
  std::string error;
};

OpenAttribute open_attribute(hid_t file, std::string_view object, std::string_view name) {
  OpenAttribute a;
  Handle obj(H5Oopen(file, object_name(object).c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.valid()) {
    a.error = with_reason("cannot open object to read attribute '" + std::string(name) + "'");
    return a;
  }
  a.attr = Handle(H5Aopen(obj.get(), std::string(name).c_str(), H5P_DEFAULT), H5Aclose);
  if (!a.attr.valid()) {
    a.error = with_reason("cannot open attribute '" + std::string(name) + "'");
    return a;
  }
  a.type = Handle(H5Aget_type(a.attr.get()), H5Tclose);
  a.space = Handle(H5Aget_space(a.attr.get()), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(a.space.get());
  if (n < 0) {
    a.error = "cannot query attribute '" + std::string(name) + "'";
    a.attr.reset();
    return a;
  }
  a.count = static_cast<hsize_t>(n);
  return a;
}

}  // namespace

#define DC_OPEN_ATTRIBUTE(var, object, name) \
  OpenAttribute var = open_attribute(id_, object, name); \
  if (!var.attr.valid()) fail(object, var.error)

std::string H5File::attribute_string(std::string_view object, std::string_view name) const {
  require_open();
  const ErrorSilencer quiet;
  DC_OPEN_ATTRIBUTE(a, object, name);
  if (H5Tget_class(a.type.get()) != H5T_STRING) fail(object, attr_label(name) + " is not a string");
  if (a.count != 1) fail(object, attr_label(name) + " holds " + std::to_string(a.count) + " strings, not one");
  std::vector<std::string> out;
  auto read = [&](hid_t mem, void* buf) { return H5Aread(a.attr.get(), mem, buf); };
  if (!read_string_values(a.type.get(), a.space.get(), 1, read, out)) fail(object, "cannot read " + attr_label(name));
  Handle obj(H5Oopen(id_, object_name(object).c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.valid()) fail(object, "cannot open object to check " + attr_label(name));
  verify_strings(obj.get(), object, out, name);
  return out.front();
}

template <H5Element T>
std::vector<T> H5File::attribute_array(std::string_view object, std::string_view name) const {
  require_open();
  const ErrorSilencer quiet;
  DC_OPEN_ATTRIBUTE(a, object, name);
  const std::optional<H5Type> stored = classify(a.type.get());
  if (!stored || !converts_losslessly(*stored, type_of<T>())) {
    fail(object, attr_label(name) + " holds " + (stored ? to_string(*stored) : "a non-numeric type") + " but " +
                     to_string(type_of<T>()) + " was requested");
  }
  if (!plausible_allocation(id_, {a.count}, sizeof(T)))
    fail(object, attr_label(name) + " claims " + std::to_string(a.count) + " values, more than the file can hold");
  std::vector<T> out(static_cast<std::size_t>(a.count));
  if (!out.empty() && H5Aread(a.attr.get(), memory_type(type_of<T>()), out.data()) < 0)
    fail(object, "cannot read " + attr_label(name));
  return out;
}

template <H5Element T>
T H5File::attribute(std::string_view object, std::string_view name) const {
  const std::vector<T> v = attribute_array<T>(object, name);
  if (v.size() != 1) fail(object, attr_label(name) + " holds " + std::to_string(v.size()) + " values, not one");
  return v.front();
}

std::vector<std::string> H5File::attribute_names(std::string_view object) const {
  require_open();
  const ErrorSilencer quiet;
  Handle obj(H5Oopen(id_, object_name(object).c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.valid()) fail(object, "cannot open object to list attributes");
  std::vector<std::string> names;
  auto collect = [](hid_t, const char* n, const H5A_info_t*, void* data) -> herr_t {
    if (!is_checksum_attribute(n)) static_cast<std::vector<std::string>*>(data)->emplace_back(n);
    return 0;
  };
  hsize_t index = 0;
  if (H5Aiterate2(obj.get(), H5_INDEX_NAME, H5_ITER_INC, &index, collect, &names) < 0)
    fail(object, "cannot list attributes");
  return names;
}

#undef DC_OPEN_ATTRIBUTE

// ---- explicit instantiations ----------------------------------------------------------------

#define DC_H5_INSTANTIATE(T)                                                                            \
  template void H5File::set_attribute<T>(std::string_view, std::string_view, T);                        \
  template void H5File::set_attribute_array<T>(std::string_view, std::string_view, std::span<const T>); \
  template T H5File::attribute<T>(std::string_view, std::string_view) const;                            \
  template std::vector<T> H5File::attribute_array<T>(std::string_view, std::string_view) const;

DC_H5_INSTANTIATE(double)
DC_H5_INSTANTIATE(float)
DC_H5_INSTANTIATE(std::int32_t)
DC_H5_INSTANTIATE(std::int64_t)
DC_H5_INSTANTIATE(std::uint8_t)
#undef DC_H5_INSTANTIATE

}  // namespace dc
