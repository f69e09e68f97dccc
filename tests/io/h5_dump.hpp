#pragma once
// Reads every group, dataset and attribute of an HDF5 file through dc::H5File into one text
// (values as exact bit patterns), so that two files — or a file before and after damage —
// can be compared for any difference a reader could see.
#include <bit>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"

namespace dc::test {

inline std::string hex_of(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(std::bit_cast<std::uint64_t>(v)));
  return buf;
}

/// Tries `read` for each of string, float64 and int64 (attributes: this layer has no type
/// query) and returns the first that works; rethrows the last IoError.
inline std::string dump_attribute(const H5File& f, const std::string& object, const std::string& name) {
  try {
    return "s:" + f.attribute_string(object, name);
  } catch (const IoError&) {
  }
  try {
    std::string out = "d:";
    for (const double v : f.attribute_array<double>(object, name)) out += hex_of(v) + ",";
    return out;
  } catch (const IoError&) {
  }
  std::string out = "i:";
  for (const std::int64_t v : f.attribute_array<std::int64_t>(object, name)) out += std::to_string(v) + ",";
  return out;
}

inline void dump_object(const H5File& f, const std::string& path, std::string& out) {
  out += path + "\n";
  for (const std::string& a : f.attribute_names(path)) out += "  @" + a + "=" + dump_attribute(f, path, a) + "\n";
  if (f.is_dataset(path)) {
    out += "  shape " + to_string(f.shape(path)) + "\n  ";
    bool numeric = true;
    try {
      (void)f.type(path);
    } catch (const IoError&) {
      numeric = false;  // strings
    }
    if (!numeric) {
      for (const std::string& s : f.read_strings(path)) out += s + "|";
    } else if (f.type(path) == H5Type::Int64) {
      for (const std::int64_t v : f.read<std::int64_t>(path)) out += std::to_string(v) + ",";
    } else {
      for (const double v : f.read<double>(path)) out += hex_of(v) + ",";
    }
    out += "\n";
    return;
  }
  const std::string prefix = path == "/" ? "/" : path + "/";
  for (const std::string& child : f.children(path)) dump_object(f, prefix + child, out);
}

/// Every value of the file as text; throws what H5File throws on a damaged file.
inline std::string dump_h5(const std::string& path) {
  const H5File f = H5File::open_read(path);
  std::string out;
  dump_object(f, "/", out);
  return out;
}

}  // namespace dc::test
