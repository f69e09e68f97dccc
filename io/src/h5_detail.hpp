#pragma once
// Internals of the HDF5 layer shared by h5.cpp, h5_attributes.cpp and atomic_h5_file.cpp
// (private to dc_io: this is the only place besides them that includes <hdf5.h>).
#include <hdf5.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "dc/io/h5.hpp"
#include "h5_checksum.hpp"

namespace dc::h5_detail {

/// Switches HDF5's automatic error printing off for one scope and restores the previous
/// handler afterwards. With a thread-safe libhdf5 the setting is per thread, so this does
/// not disturb other threads; no state outlives the scope.
class ErrorSilencer {
 public:
  ErrorSilencer() {
    if (H5Eget_auto2(H5E_DEFAULT, &func_, &data_) < 0) func_ = nullptr, data_ = nullptr;
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~ErrorSilencer() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  ErrorSilencer(const ErrorSilencer&) = delete;
  ErrorSilencer& operator=(const ErrorSilencer&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

/// The most specific description on HDF5's error stack (e.g. "truncated file: eof = ..."),
/// then clears the stack. Empty when HDF5 recorded nothing.
inline std::string hdf5_reason() {
  std::string out;
  auto walk = [](unsigned n, const H5E_error2_t* e, void* data) -> herr_t {
    if (n == 0 && e->desc != nullptr) *static_cast<std::string*>(data) = e->desc;
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk, &out);
  H5Eclear2(H5E_DEFAULT);
  // A failed POSIX write is described with time, buffer address and sizes; its cause is the
  // system's message ("file write failed: No space left on device").
  if (const std::size_t at = out.find("error message = '"); at != std::string::npos) {
    const std::size_t from = at + 17, to = out.find('\'', from);
    const std::size_t colon = out.find(':');
    if (to != std::string::npos && colon != std::string::npos && colon < at)
      out = out.substr(0, colon) + ": " + out.substr(from, to - from);
  }
  for (char& c : out)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  return out;
}

/// `what` plus HDF5's reason, captured now — before a later successful HDF5 call (even a
/// cleanup H5?close) resets the error stack.
/// A failed checksum (a chunk's Fletcher-32 or a metadata checksum) is named as such: a bit
/// flip on disk must read as damage, not as a puzzling HDF5 internals message.
inline std::string with_reason(std::string what) {
  if (const std::string reason = hdf5_reason(); !reason.empty()) {
    if (const std::string damage = checksum_failure(reason); !damage.empty()) what += ": " + damage;
    what += " (HDF5: " + reason + ")";
  }
  return what;
}

/// True if HDF5's error stack records a failed low-level write (H5E_IO/H5E_WRITEERROR): a
/// full disk (ENOSPC) or a file-size limit (EFBIG). Leaves the stack as it is.
inline bool write_failed_on_stack() {
  bool found = false;
  auto walk = [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
    if (e->maj_num == H5E_IO && e->min_num == H5E_WRITEERROR) *static_cast<bool*>(data) = true;
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk, &found);
  return found;
}

/// After a failed write, libhdf5 1.10.8 cannot close the file: a flush that fails leaves its
/// metadata cache's skip list enabled, so every later flush and H5Fclose fail ("slist already
/// enabled?"), the id stays, and the library's own cleanup at exit crashes on it (SIGSEGV).
/// So a failed write must be seen where it happens (every write path checks its H5Dwrite and
/// the dataset's close, which writes the chunk cache, while the error stack still says why),
/// and the file's descriptor is then pointed at a sink before any flush: what the close still
/// writes lands there and vanishes, the close succeeds, and the file on disk stays as a crash
/// at the moment of the failure would have left it (the readers refuse such a file with an
/// IoError; `generate --resume` cuts it back). The sink is an anonymous in-memory file
/// (memfd). Under a file-size limit (EFBIG) the close still fails — it truncates the file to a
/// size past the limit, in a memfd as on disk — which is why a program calls
/// h5_skip_exit_cleanup() (h5.hpp). Only for the default sec2 driver, whose handle is the
/// POSIX descriptor.
inline void abandon_writes(hid_t file) {
  const hid_t fapl = H5Fget_access_plist(file);
  if (fapl < 0) return;
  const hid_t driver = H5Pget_driver(fapl);
  H5Pclose(fapl);
  void* handle = nullptr;
  if (driver != H5FD_SEC2 || H5Fget_vfd_handle(file, H5P_DEFAULT, &handle) < 0 || handle == nullptr) return;
  const int sink = ::memfd_create("dc-abandoned-hdf5", MFD_CLOEXEC);
  if (sink < 0) return;
  ::dup2(sink, *static_cast<int*>(handle));  // closes the disk file, keeps the descriptor number
  ::close(sink);
}

/// Closes a file id, first flushing a writable one so that a full disk shows up where the
/// file can still be abandoned. Returns HDF5's reason when the flush or the close failed.
inline std::optional<std::string> close_file(hid_t id, bool writable) {
  std::optional<std::string> error;
  if (writable && H5Fflush(id, H5F_SCOPE_GLOBAL) < 0) {
    const bool io = write_failed_on_stack();
    error = with_reason("flush failed");  // before abandon_writes' calls reset the stack
    if (io) abandon_writes(id);
  }
  if (H5Fclose(id) < 0 && !error) error = with_reason("close failed");
  H5Eclear2(H5E_DEFAULT);
  return error;
}

/// Owns one HDF5 id and closes it with the matching H5?close.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, -1)), close_(o.close_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, -1);
      close_ = o.close_;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  void reset() { (void)close(); }
  /// Closes the id now and returns what the close returned (< 0: failed; HDF5's error stack
  /// holds why). Closing a dataset writes its cached chunks: a write path closes it this way
  /// and checks, so a full disk is seen there and not only at a later flush of the file.
  herr_t close() {
    const herr_t rc = id_ >= 0 && close_ != nullptr ? close_(id_) : 0;
    id_ = -1;
    return rc;
  }
  [[nodiscard]] hid_t get() const { return id_; }
  [[nodiscard]] bool valid() const { return id_ >= 0; }

 private:
  hid_t id_ = -1;
  herr_t (*close_)(hid_t) = nullptr;
};

inline std::string object_name(std::string_view path) {
  if (path.empty()) return "/";
  return path.front() == '/' ? std::string(path) : "/" + std::string(path);
}

template <H5Element T>
constexpr H5Type type_of() {
  if constexpr (std::is_same_v<T, double>) return H5Type::Float64;
  else if constexpr (std::is_same_v<T, float>) return H5Type::Float32;
  else if constexpr (std::is_same_v<T, std::int32_t>) return H5Type::Int32;
  else if constexpr (std::is_same_v<T, std::int64_t>) return H5Type::Int64;
  else return H5Type::UInt8;
}

inline hid_t memory_type(H5Type t) {
  switch (t) {
    case H5Type::Float64: return H5T_NATIVE_DOUBLE;
    case H5Type::Float32: return H5T_NATIVE_FLOAT;
    case H5Type::Int32: return H5T_NATIVE_INT32;
    case H5Type::Int64: return H5T_NATIVE_INT64;
    case H5Type::UInt8: return H5T_NATIVE_UINT8;
  }
  return -1;
}

/// Little-endian on disk regardless of the machine, so files compare byte-for-byte.
inline hid_t file_type(H5Type t) {
  switch (t) {
    case H5Type::Float64: return H5T_IEEE_F64LE;
    case H5Type::Float32: return H5T_IEEE_F32LE;
    case H5Type::Int32: return H5T_STD_I32LE;
    case H5Type::Int64: return H5T_STD_I64LE;
    case H5Type::UInt8: return H5T_STD_U8LE;
  }
  return -1;
}

/// Classifies a stored datatype; nullopt for anything this layer does not handle.
inline std::optional<H5Type> classify(hid_t type) {
  const H5T_class_t cls = H5Tget_class(type);
  const std::size_t size = H5Tget_size(type);
  if (cls == H5T_FLOAT) {
    if (size == 8) return H5Type::Float64;
    if (size == 4) return H5Type::Float32;
  } else if (cls == H5T_INTEGER) {
    const bool is_signed = H5Tget_sign(type) == H5T_SGN_2;
    if (is_signed && size == 4) return H5Type::Int32;
    if (is_signed && size == 8) return H5Type::Int64;
    if (!is_signed && size == 1) return H5Type::UInt8;
  }
  return std::nullopt;
}

/// Whether HDF5's conversion from `stored` to `wanted` is exact for every value.
inline bool converts_losslessly(H5Type stored, H5Type wanted) {
  if (stored == wanted || stored == H5Type::UInt8) return true;
  switch (wanted) {
    case H5Type::Float64: return stored == H5Type::Float32 || stored == H5Type::Int32;
    case H5Type::Int64: return stored == H5Type::Int32;
    default: return false;
  }
}

/// Product of the extents from axis `from` on; the largest hsize_t when it overflows (a
/// damaged extent), which no allocation or data size matches.
inline hsize_t product(const H5Shape& s, std::size_t from = 0) {
  hsize_t p = 1;
  for (std::size_t i = from; i < s.size(); ++i)
    if (__builtin_mul_overflow(p, s[i], &p)) return std::numeric_limits<hsize_t>::max();
  return p;
}

/// True when `dims` elements of `element_size` bytes can be counted in std::size_t (checked
/// before allocating what a file's header announces).
inline bool countable(const H5Shape& dims, std::size_t element_size) {
  std::size_t bytes = element_size;
  for (const hsize_t d : dims)
    if (d > std::numeric_limits<std::size_t>::max() || __builtin_mul_overflow(bytes, static_cast<std::size_t>(d), &bytes))
      return false;
  return bytes <= static_cast<std::size_t>(std::numeric_limits<std::ptrdiff_t>::max());
}

/// File-access properties of every file this layer creates: the HDF5 1.10 file format (low
/// and high bound), whose superblock, object headers, B-trees, heaps of links and chunk
/// indexes all carry checksums that HDF5 verifies on every read (h5_checksum.hpp). Readable by
/// HDF5 ≥ 1.10 (h5py built on it). Invalid handle on failure.
inline Handle file_access_with_checksums() {
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (fapl.valid() && H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V110, H5F_LIBVER_LATEST) < 0) fapl.reset();
  return fapl;
}

/// Links and attributes stay in the object header ("compact" storage, up to 65535 of each)
/// instead of moving to "dense" storage past 8: dense storage keeps them in a fractal heap
/// whose direct blocks HDF5 does not checksum by default, and a damaged one crashed libhdf5
/// 1.10.8 (H5G__dense_iterate freeing garbage) in the bit-flip test. Object headers carry a
/// checksum. Applied to a group, dataset or file creation property list; false on failure.
inline bool keep_links_and_attributes_compact(hid_t plist, bool group) {
  return H5Pset_attr_phase_change(plist, 65535, 65535) >= 0 &&
         (!group || H5Pset_link_phase_change(plist, 65535, 65535) >= 0);
}

/// Group-creation properties of every group this layer creates (keep_links_and_attributes_compact).
inline Handle group_creation() {
  Handle gcpl(H5Pcreate(H5P_GROUP_CREATE), H5Pclose);
  if (gcpl.valid() && !keep_links_and_attributes_compact(gcpl.get(), true)) gcpl.reset();
  return gcpl;
}

/// File-creation properties: the root group's links and attributes compact as well.
inline Handle file_creation() {
  Handle fcpl(H5Pcreate(H5P_FILE_CREATE), H5Pclose);
  if (fcpl.valid() && !keep_links_and_attributes_compact(fcpl.get(), true)) fcpl.reset();
  return fcpl;
}

/// Creates the missing parent groups of `path` ("/a" and "/a/b" for "/a/b/c") with
/// group_creation(), so that no group gets HDF5's default (dense past 8 links) properties.
/// False when one cannot be created.
inline bool create_parent_groups(hid_t file, const std::string& path) {
  const Handle gcpl = group_creation();
  for (std::size_t pos = path.find('/', 1); pos != std::string::npos; pos = path.find('/', pos + 1)) {
    const std::string prefix = path.substr(0, pos);
    const htri_t exists = H5Lexists(file, prefix.c_str(), H5P_DEFAULT);
    if (exists > 0) continue;
    Handle g(H5Gcreate2(file, prefix.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), H5Gclose);
    if (!g.valid()) return false;
  }
  return true;
}

/// Link-creation properties that create missing parent groups ("/a/b" for "/a/b/c").
inline Handle intermediate_groups_lcpl() {
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  if (lcpl.valid()) H5Pset_create_intermediate_group(lcpl.get(), 1);
  return lcpl;
}

/// A string datatype: variable-length or fixed `size` bytes, NUL-padded, UTF-8.
inline Handle string_type(H5StringKind kind, std::size_t size) {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!t.valid()) return t;
  H5Tset_size(t.get(), kind == H5StringKind::Variable ? H5T_VARIABLE : std::max<std::size_t>(size, 1));
  if (kind == H5StringKind::Fixed) H5Tset_strpad(t.get(), H5T_STR_NULLPAD);
  H5Tset_cset(t.get(), H5T_CSET_UTF8);
  return t;
}

/// A damaged file can announce any extent, and a reader that allocates what the header says
/// (rather than what the file holds) turns a flipped byte into a multi-terabyte allocation.
/// Deflate expands at most ~1032:1, so no honest dataset or attribute holds more than ~1100 times
/// the file's size (+1 MiB of slack for small files and fill values). Computed in long double:
/// the product of a damaged extent may overflow hsize_t.
inline bool plausible_allocation(hid_t file, const H5Shape& dims, std::size_t element_size) {
  hsize_t file_size = 0;
  if (H5Fget_filesize(file, &file_size) < 0) return true;  // cannot tell: HDF5 decides
  long double bytes = static_cast<long double>(element_size);
  for (const hsize_t d : dims) bytes *= static_cast<long double>(d);
  return bytes <= 1100.0L * static_cast<long double>(file_size) + 1048576.0L;
}

/// Reads `n` strings from a dataset or attribute with stored string type `stored`.
/// `read(mem_type, buffer)` performs the H5Dread/H5Aread.
template <class ReadFn>
bool read_string_values(hid_t stored, hid_t space, hsize_t n, ReadFn read, std::vector<std::string>& out) {
  if (H5Tis_variable_str(stored) > 0) {
    Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mem.get(), H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(stored));
    std::vector<char*> ptrs(n, nullptr);
    if (read(mem.get(), static_cast<void*>(ptrs.data())) < 0) {
      // A read that fails part-way (a damaged heap object in a truncated or corrupt file)
      // has already allocated the strings before it: free them (null entries are skipped).
      H5Dvlen_reclaim(mem.get(), space, H5P_DEFAULT, ptrs.data());
      return false;
    }
    out.clear();
    for (char* p : ptrs) out.emplace_back(p != nullptr ? p : "");
    // The library allocated each string; give them back.
    H5Dvlen_reclaim(mem.get(), space, H5P_DEFAULT, ptrs.data());
    return true;
  }
  const std::size_t size = H5Tget_size(stored);
  Handle mem(H5Tcopy(stored), H5Tclose);
  std::vector<char> buffer(static_cast<std::size_t>(n) * size);
  if (read(mem.get(), static_cast<void*>(buffer.data())) < 0) return false;
  const bool space_padded = H5Tget_strpad(stored) == H5T_STR_SPACEPAD;
  out.clear();
  for (hsize_t i = 0; i < n; ++i) {
    std::string s(buffer.data() + i * size, size);
    // NUL-terminated/padded: cut at the first NUL; space-padded: strip trailing blanks.
    if (const auto nul = s.find('\0'); nul != std::string::npos) s.resize(nul);
    if (space_padded) s.erase(s.find_last_not_of(' ') + 1);
    out.push_back(std::move(s));
  }
  return true;
}

}  // namespace dc::h5_detail
