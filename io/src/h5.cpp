// RAII layer on the HDF5 C API (see h5.hpp for the conventions).
//
// Every public member starts with an ErrorSilencer (HDF5 must not print its error stack
// to stderr; we turn failures into one-line IoErrors instead) and closes every id it
// opens through Handle, so no HDF5 object outlives the call that opened it — that keeps
// H5Fclose's default "weak" close degree from ever leaving a file silently open.
#include "dc/io/h5.hpp"

#include <hdf5.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <numeric>
#include <utility>

#include "dc/engine/error.hpp"
#include "dc/io/atomic_file.hpp"

namespace dc {

// h5.hpp declares HDF5's two integer types itself so that it need not include <hdf5.h>.
static_assert(std::is_same_v<dc::hsize_t, ::hsize_t>, "dc::hsize_t must be HDF5's hsize_t");
static_assert(std::is_same_v<std::int64_t, ::hid_t>, "H5File::Id (std::int64_t) must be HDF5's hid_t");

namespace {

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
std::string hdf5_reason() {
  std::string out;
  auto walk = [](unsigned n, const H5E_error2_t* e, void* data) -> herr_t {
    if (n == 0 && e->desc != nullptr) *static_cast<std::string*>(data) = e->desc;
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk, &out);
  H5Eclear2(H5E_DEFAULT);
  for (char& c : out)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  return out;
}

/// `what` plus HDF5's reason, captured now — before a later successful HDF5 call (even a
/// cleanup H5?close) resets the error stack.
std::string with_reason(std::string what) {
  if (const std::string reason = hdf5_reason(); !reason.empty()) what += " (HDF5: " + reason + ")";
  return what;
}

/// True if HDF5's error stack records a failed low-level read/write/truncate (H5E_IO): on a
/// writable file, a full disk (ENOSPC) or a file-size limit (EFBIG). Leaves the stack as is.
bool io_failed_on_stack() {
  bool found = false;
  auto walk = [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
    if (e->maj_num == H5E_IO) *static_cast<bool*>(data) = true;
    return 0;
  };
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk, &found);
  return found;
}

/// After a failed write, libhdf5 1.10.8 can no longer close the file: H5Fclose retries the
/// writes, fails, and leaves a dangling id on which the library's own cleanup at exit then
/// crashes (SIGSEGV). So the file's descriptor is pointed at an anonymous in-memory file
/// (memfd): what the close still writes lands there and vanishes, the close succeeds, and
/// the file on disk stays as a crash at the moment of the failure would have left it (the
/// readers refuse such a file with an IoError; `generate --resume` cuts it back). Only for
/// the default sec2 driver, whose handle is the POSIX descriptor.
void abandon_writes(hid_t file) {
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
std::optional<std::string> close_file(hid_t id, bool writable) {
  std::optional<std::string> error;
  if (writable && H5Fflush(id, H5F_SCOPE_GLOBAL) < 0) {
    const bool io = io_failed_on_stack();
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
  void reset() {
    if (id_ >= 0 && close_ != nullptr) close_(id_);
    id_ = -1;
  }
  [[nodiscard]] hid_t get() const { return id_; }
  [[nodiscard]] bool valid() const { return id_ >= 0; }

 private:
  hid_t id_ = -1;
  herr_t (*close_)(hid_t) = nullptr;
};

std::string object_name(std::string_view path) {
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

hid_t memory_type(H5Type t) {
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
hid_t file_type(H5Type t) {
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
std::optional<H5Type> classify(hid_t type) {
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
bool converts_losslessly(H5Type stored, H5Type wanted) {
  if (stored == wanted || stored == H5Type::UInt8) return true;
  switch (wanted) {
    case H5Type::Float64: return stored == H5Type::Float32 || stored == H5Type::Int32;
    case H5Type::Int64: return stored == H5Type::Int32;
    default: return false;
  }
}

hsize_t product(const H5Shape& s, std::size_t from = 0) {
  hsize_t p = 1;
  for (std::size_t i = from; i < s.size(); ++i) p *= s[i];
  return p;
}

/// Link-creation properties that create missing parent groups ("/a/b" for "/a/b/c").
Handle intermediate_groups_lcpl() {
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  if (lcpl.valid()) H5Pset_create_intermediate_group(lcpl.get(), 1);
  return lcpl;
}

/// A string datatype: variable-length or fixed `size` bytes, NUL-padded, UTF-8.
Handle string_type(H5StringKind kind, std::size_t size) {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!t.valid()) return t;
  H5Tset_size(t.get(), kind == H5StringKind::Variable ? H5T_VARIABLE : std::max<std::size_t>(size, 1));
  if (kind == H5StringKind::Fixed) H5Tset_strpad(t.get(), H5T_STR_NULLPAD);
  H5Tset_cset(t.get(), H5T_CSET_UTF8);
  return t;
}

/// A damaged file can announce any extent, and a reader that allocates what the header says
/// (rather than what the file holds) turns a flipped byte into a multi-terabyte allocation.
/// Deflate expands at most ~1032:1, so no honest dataset or attribute holds more than ~1100×
/// the file's size (+1 MiB of slack for small files and fill values). Computed in long double:
/// the product of a damaged extent may overflow hsize_t.
bool plausible_allocation(hid_t file, const H5Shape& dims, std::size_t element_size) {
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

}  // namespace

const char* to_string(H5Type t) {
  switch (t) {
    case H5Type::Float64: return "float64";
    case H5Type::Float32: return "float32";
    case H5Type::Int32: return "int32";
    case H5Type::Int64: return "int64";
    case H5Type::UInt8: return "uint8";
  }
  return "?";
}

std::string to_string(const H5Shape& shape) {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (i > 0) s += ',';
    s += shape[i] == kH5Any ? std::string("*") : std::to_string(shape[i]);
  }
  return s + ")";
}

// ---- H5File: lifetime ---------------------------------------------------------------------

H5File::H5File(std::string path, Id id, bool writable) : path_(std::move(path)), id_(id), writable_(writable) {}

H5File::H5File(H5File&& o) noexcept
    : path_(std::move(o.path_)), id_(std::exchange(o.id_, -1)), writable_(o.writable_) {}

H5File& H5File::operator=(H5File&& o) noexcept {
  if (this != &o) {
    if (id_ >= 0) {
      const ErrorSilencer quiet;
      (void)close_file(id_, writable_);
    }
    path_ = std::move(o.path_);
    id_ = std::exchange(o.id_, -1);
    writable_ = o.writable_;
  }
  return *this;
}

H5File::~H5File() {
  if (id_ >= 0) {
    const ErrorSilencer quiet;
    (void)close_file(id_, writable_);
  }
}

void H5File::fail(std::string_view object, const std::string& what) const {
  const bool io = writable_ && id_ >= 0 && io_failed_on_stack();
  const std::string message = path_ + ": " + object_name(object) + ": " + with_reason(what);
  if (io) abandon_writes(id_);
  throw IoError(message);
}

void H5File::require_open() const {
  if (id_ < 0) throw InvalidArgument(path_ + ": HDF5 file is closed");
}

void H5File::require_writable(std::string_view object) const {
  require_open();
  if (!writable_) throw IoError(path_ + ": " + object_name(object) + ": file is open read-only");
}

H5File H5File::create(const std::string& path) {
  const ErrorSilencer quiet;
  const hid_t id = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (id < 0) throw IoError(path + ": " + with_reason("cannot create HDF5 file"));
  return H5File(path, id, true);
}

H5File H5File::open(const std::string& path, bool writable) {
  const ErrorSilencer quiet;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw IoError(path + ": cannot open HDF5 file: no such file");
  if (!std::filesystem::is_regular_file(path, ec)) throw IoError(path + ": cannot open HDF5 file: not a regular file");
  // H5Fis_hdf5 only looks for the signature, so it tells "not HDF5 at all" apart from
  // "HDF5 but damaged" (which H5Fopen detects, e.g. a truncated file's short EOF).
  const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
  if (is_hdf5 == 0) {
    H5Eclear2(H5E_DEFAULT);
    throw IoError(path + ": not an HDF5 file");
  }
  const hid_t id = H5Fopen(path.c_str(), writable ? H5F_ACC_RDWR : H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0) throw IoError(path + ": " + with_reason("cannot open HDF5 file (truncated or damaged?)"));
  return H5File(path, id, writable);
}

H5File H5File::open_read(const std::string& path) { return open(path, false); }
H5File H5File::open_rw(const std::string& path) { return open(path, true); }

void H5File::flush() {
  require_open();
  const ErrorSilencer quiet;
  if (H5Fflush(id_, H5F_SCOPE_GLOBAL) < 0) fail("/", "flush failed");
}

void H5File::close() {
  if (id_ < 0) return;
  const ErrorSilencer quiet;
  if (const auto error = close_file(std::exchange(id_, -1), writable_)) throw IoError(path_ + ": /: " + *error);
}

// ---- objects ------------------------------------------------------------------------------

bool H5File::exists(std::string_view path) const {
  require_open();
  const ErrorSilencer quiet;
  const std::string name = object_name(path);
  if (name == "/") return true;
  // H5Lexists fails (rather than answering false) when a parent is missing, so walk down.
  std::size_t pos = 0;
  while (pos != std::string::npos) {
    pos = name.find('/', pos + 1);
    const std::string prefix = name.substr(0, pos);
    if (prefix.size() <= 1) continue;
    if (H5Lexists(id_, prefix.c_str(), H5P_DEFAULT) <= 0) {
      H5Eclear2(H5E_DEFAULT);
      return false;
    }
  }
  const htri_t ok = H5Oexists_by_name(id_, name.c_str(), H5P_DEFAULT);  // false for dangling links
  H5Eclear2(H5E_DEFAULT);
  return ok > 0;
}

namespace {
H5I_type_t object_type(hid_t file, const std::string& name) {
  Handle obj(H5Oopen(file, name.c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.valid()) {
    H5Eclear2(H5E_DEFAULT);
    return H5I_BADID;
  }
  return H5Iget_type(obj.get());
}
}  // namespace

bool H5File::is_group(std::string_view path) const {
  if (!exists(path)) return false;
  const ErrorSilencer quiet;
  return object_type(id_, object_name(path)) == H5I_GROUP;
}

bool H5File::is_dataset(std::string_view path) const {
  if (!exists(path)) return false;
  const ErrorSilencer quiet;
  return object_type(id_, object_name(path)) == H5I_DATASET;
}

void H5File::create_group(std::string_view path) {
  require_writable(path);
  if (exists(path)) {
    if (!is_group(path)) fail(path, "cannot create group: a dataset of that name exists");
    return;
  }
  const ErrorSilencer quiet;
  const Handle lcpl = intermediate_groups_lcpl();
  Handle g(H5Gcreate2(id_, object_name(path).c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail(path, "cannot create group");
}

std::vector<std::string> H5File::children(std::string_view group) const {
  require_open();
  const ErrorSilencer quiet;
  Handle g(H5Gopen2(id_, object_name(group).c_str(), H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail(group, "cannot open group");
  std::vector<std::string> names;
  auto collect = [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
    static_cast<std::vector<std::string>*>(data)->emplace_back(name);
    return 0;
  };
  hsize_t index = 0;
  if (H5Literate(g.get(), H5_INDEX_NAME, H5_ITER_INC, &index, collect, &names) < 0) fail(group, "cannot list group");
  return names;
}

void H5File::remove(std::string_view path) {
  require_writable(path);
  const ErrorSilencer quiet;
  if (H5Ldelete(id_, object_name(path).c_str(), H5P_DEFAULT) < 0) fail(path, "cannot remove object");
}

void H5File::remove_attribute(std::string_view object, std::string_view name) {
  require_writable(object);
  const ErrorSilencer quiet;
  if (H5Adelete_by_name(id_, object_name(object).c_str(), std::string(name).c_str(), H5P_DEFAULT) < 0)
    fail(object, "cannot remove attribute " + std::string(name));
}

// ---- numeric datasets ---------------------------------------------------------------------

template <H5Element T>
void H5File::create_dataset(std::string_view path, const H5Shape& shape, const H5DatasetOptions& options) {
  require_writable(path);
  if (options.deflate < 0 || options.deflate > 9)
    throw InvalidArgument(path_ + ": " + object_name(path) + ": deflate level must be in 0..9");
  const bool chunked = options.extendible || options.deflate > 0;
  if (chunked && shape.empty())
    throw InvalidArgument(path_ + ": " + object_name(path) + ": a scalar dataset cannot be extendible or compressed");
  if (exists(path)) fail(path, "cannot create dataset: an object of that name exists");

  const ErrorSilencer quiet;
  H5Shape maxdims = shape;
  if (options.extendible) maxdims[0] = H5S_UNLIMITED;
  Handle space(shape.empty() ? H5Screate(H5S_SCALAR)
                             : H5Screate_simple(static_cast<int>(shape.size()), shape.data(), maxdims.data()),
               H5Sclose);
  if (!space.valid()) fail(path, "cannot create dataspace " + to_string(shape));

  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (chunked) {
    // Whole rows per chunk: appends and row reads touch few chunks, and ≈ 256 KiB keeps
    // compression effective without making single-row reads expensive.
    H5Shape chunk(shape.size());
    for (std::size_t i = 1; i < shape.size(); ++i) chunk[i] = std::max<hsize_t>(shape[i], 1);
    const hsize_t row_bytes = product(chunk, 1) * sizeof(T);
    hsize_t rows = options.chunk_rows;
    if (rows == 0) {
      rows = std::max<hsize_t>(1, (hsize_t{256} << 10) / row_bytes);
      if (!options.extendible) rows = std::min(rows, std::max<hsize_t>(shape[0], 1));
    }
    chunk[0] = rows;
    if (H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()) < 0)
      fail(path, "cannot set chunk shape " + to_string(chunk));
    if (options.deflate > 0 &&
        (H5Pset_shuffle(dcpl.get()) < 0 || H5Pset_deflate(dcpl.get(), static_cast<unsigned>(options.deflate)) < 0))
      fail(path, "cannot enable deflate compression");
  }
  const Handle lcpl = intermediate_groups_lcpl();
  Handle ds(H5Dcreate2(id_, object_name(path).c_str(), file_type(type_of<T>()), space.get(), lcpl.get(), dcpl.get(),
                       H5P_DEFAULT),
            H5Dclose);
  if (!ds.valid()) fail(path, std::string("cannot create ") + to_string(type_of<T>()) + " dataset " + to_string(shape));
}

namespace {

/// An open dataset with its shape, maximum shape and stored type (for checks); `error`
/// says what failed when `ds` is invalid.
struct OpenDataset {
  Handle ds;
  H5Shape dims;
  H5Shape maxdims;
  std::optional<H5Type> type;
  std::string error;
};

OpenDataset open_dataset(hid_t file, std::string_view path, std::string_view op) {
  OpenDataset d;
  d.ds = Handle(H5Dopen2(file, object_name(path).c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.ds.valid()) {
    d.error = with_reason("cannot open dataset to " + std::string(op));
    return d;
  }
  Handle space(H5Dget_space(d.ds.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) {
    d.error = with_reason("cannot query the dataspace of the dataset to " + std::string(op));
    d.ds.reset();
    return d;
  }
  d.dims.resize(static_cast<std::size_t>(rank));
  d.maxdims.resize(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.get(), d.dims.data(), d.maxdims.data());
  Handle type(H5Dget_type(d.ds.get()), H5Tclose);
  d.type = classify(type.get());
  return d;
}

}  // namespace

/// Opens the dataset at `path` for operation `op` or throws IoError naming both.
#define DC_OPEN_DATASET(var, path, op) \
  OpenDataset var = open_dataset(id_, path, op); \
  if (!var.ds.valid()) fail(path, var.error)

template <H5Element T>
void H5File::write(std::string_view path, std::span<const T> data, const H5Shape& shape,
                   const H5DatasetOptions& options) {
  if (data.size() != product(shape)) {
    throw InvalidArgument(path_ + ": " + object_name(path) + ": " + std::to_string(data.size()) +
                          " values given for shape " + to_string(shape));
  }
  create_dataset<T>(path, shape, options);
  if (data.empty()) return;
  const ErrorSilencer quiet;
  Handle ds(H5Dopen2(id_, object_name(path).c_str(), H5P_DEFAULT), H5Dclose);
  if (!ds.valid() || H5Dwrite(ds.get(), memory_type(type_of<T>()), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    fail(path, "cannot write dataset");
}

namespace {
/// Writes `data` into rows [first, first + rows) of an open dataset.
bool write_row_block(hid_t ds, const H5Shape& dims, hsize_t first, hsize_t rows, hid_t mem_type, const void* data) {
  Handle file_space(H5Dget_space(ds), H5Sclose);
  H5Shape start(dims.size(), 0), count = dims;
  start[0] = first;
  count[0] = rows;
  Handle mem_space(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr), H5Sclose);
  return file_space.valid() && mem_space.valid() &&
         H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr) >= 0 &&
         H5Dwrite(ds, mem_type, mem_space.get(), file_space.get(), H5P_DEFAULT, data) >= 0;
}
}  // namespace

template <H5Element T>
hsize_t H5File::append_rows(std::string_view path, std::span<const T> data) {
  require_writable(path);
  const ErrorSilencer quiet;
  DC_OPEN_DATASET(d, path, "append rows");
  if (d.dims.empty()) fail(path, "cannot append rows to a scalar dataset");
  if (d.maxdims[0] != H5S_UNLIMITED) fail(path, "cannot append rows: dataset is not extendible");
  if (d.type != type_of<T>()) {
    fail(path, std::string("cannot append ") + to_string(type_of<T>()) + " rows: dataset holds " +
                   (d.type ? to_string(*d.type) : "another type"));
  }
  const hsize_t row_size = product(d.dims, 1);
  if (row_size == 0 ? !data.empty() : data.size() % row_size != 0) {
    throw InvalidArgument(path_ + ": " + object_name(path) + ": " + std::to_string(data.size()) +
                          " values are not whole rows of shape " + to_string(H5Shape(d.dims.begin() + 1, d.dims.end())));
  }
  const hsize_t rows = row_size == 0 ? 0 : data.size() / row_size;
  if (rows == 0) return d.dims[0];
  H5Shape grown = d.dims;
  grown[0] += rows;
  if (H5Dset_extent(d.ds.get(), grown.data()) < 0) fail(path, "cannot extend dataset to " + to_string(grown));
  if (!write_row_block(d.ds.get(), grown, d.dims[0], rows, memory_type(type_of<T>()), data.data()))
    fail(path, "cannot write appended rows");
  return grown[0];
}

template <H5Element T>
void H5File::write_rows(std::string_view path, hsize_t first_row, std::span<const T> data) {
  require_writable(path);
  const ErrorSilencer quiet;
  DC_OPEN_DATASET(d, path, "write rows");
  if (d.dims.empty()) fail(path, "cannot write rows of a scalar dataset");
  if (d.type != type_of<T>()) {
    fail(path, std::string("cannot write ") + to_string(type_of<T>()) + " rows: dataset holds " +
                   (d.type ? to_string(*d.type) : "another type"));
  }
  const hsize_t row_size = product(d.dims, 1);
  if (row_size == 0 || data.size() % row_size != 0) {
    throw InvalidArgument(path_ + ": " + object_name(path) + ": " + std::to_string(data.size()) +
                          " values are not whole rows of shape " + to_string(H5Shape(d.dims.begin() + 1, d.dims.end())));
  }
  const hsize_t rows = data.size() / row_size;
  if (first_row + rows > d.dims[0]) {
    fail(path, "rows [" + std::to_string(first_row) + ", " + std::to_string(first_row + rows) +
                   ") are outside the dataset's " + std::to_string(d.dims[0]) + " rows");
  }
  if (rows > 0 && !write_row_block(d.ds.get(), d.dims, first_row, rows, memory_type(type_of<T>()), data.data()))
    fail(path, "cannot write rows");
}

void H5File::resize_rows(std::string_view path, hsize_t rows) {
  require_writable(path);
  const ErrorSilencer quiet;
  DC_OPEN_DATASET(d, path, "resize");
  if (d.dims.empty()) fail(path, "cannot resize a scalar dataset");
  if (d.maxdims[0] != H5S_UNLIMITED && rows > d.maxdims[0]) fail(path, "cannot resize: dataset is not extendible");
  H5Shape dims = d.dims;
  dims[0] = rows;
  if (H5Dset_extent(d.ds.get(), dims.data()) < 0) fail(path, "cannot resize dataset to " + to_string(dims));
}

H5Shape H5File::shape(std::string_view path) const {
  require_open();
  const ErrorSilencer quiet;
  DC_OPEN_DATASET(d, path, "query its shape");
  return d.dims;
}

H5Type H5File::type(std::string_view path) const {
  require_open();
  const ErrorSilencer quiet;
  DC_OPEN_DATASET(d, path, "query its type");
  if (!d.type) fail(path, "dataset has an element type other than float64/float32/int32/int64/uint8");
  return *d.type;
}

void H5File::require_shape(std::string_view path, const H5Shape& expected) const {
  const H5Shape actual = shape(path);
  bool ok = actual.size() == expected.size();
  for (std::size_t i = 0; ok && i < actual.size(); ++i) ok = expected[i] == kH5Any || expected[i] == actual[i];
  if (!ok) fail(path, "dataset has shape " + to_string(actual) + " but " + to_string(expected) + " was expected");
}

template <H5Element T>
std::vector<T> H5File::read(std::string_view path) const {
  require_open();
  const ErrorSilencer quiet;
  DC_OPEN_DATASET(d, path, "read");
  if (!d.type || !converts_losslessly(*d.type, type_of<T>())) {
    fail(path, std::string("dataset holds ") + (d.type ? to_string(*d.type) : "an unsupported type") + " but " +
                   to_string(type_of<T>()) + " was requested");
  }
  if (!plausible_allocation(id_, d.dims, sizeof(T)))
    fail(path, "dataset shape " + to_string(d.dims) + " is more than the file can hold (damaged file?)");
  std::vector<T> out(static_cast<std::size_t>(product(d.dims)));
  if (!out.empty() && H5Dread(d.ds.get(), memory_type(type_of<T>()), H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    fail(path, "cannot read dataset");
  return out;
}

template <H5Element T>
std::vector<T> H5File::read(std::string_view path, const H5Shape& expected) const {
  require_shape(path, expected);
  return read<T>(path);
}

template <H5Element T>
std::vector<T> H5File::read_rows(std::string_view path, hsize_t first_row, hsize_t count) const {
  require_open();
  const ErrorSilencer quiet;
  DC_OPEN_DATASET(d, path, "read rows");
  if (d.dims.empty()) fail(path, "cannot read rows of a scalar dataset");
  if (!d.type || !converts_losslessly(*d.type, type_of<T>())) {
    fail(path, std::string("dataset holds ") + (d.type ? to_string(*d.type) : "an unsupported type") + " but " +
                   to_string(type_of<T>()) + " was requested");
  }
  if (first_row > d.dims[0] || count > d.dims[0] - first_row) {
    fail(path, "rows [" + std::to_string(first_row) + ", " + std::to_string(first_row + count) +
                   ") are outside the dataset's " + std::to_string(d.dims[0]) + " rows");
  }
  H5Shape block = d.dims;
  block[0] = count;
  if (!plausible_allocation(id_, block, sizeof(T)))
    fail(path, "dataset shape " + to_string(d.dims) + " is more than the file can hold (damaged file?)");
  std::vector<T> out(static_cast<std::size_t>(product(block)));
  if (out.empty()) return out;
  H5Shape start(d.dims.size(), 0);
  start[0] = first_row;
  Handle file_space(H5Dget_space(d.ds.get()), H5Sclose);
  Handle mem_space(H5Screate_simple(static_cast<int>(block.size()), block.data(), nullptr), H5Sclose);
  if (H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, block.data(), nullptr) < 0 ||
      H5Dread(d.ds.get(), memory_type(type_of<T>()), mem_space.get(), file_space.get(), H5P_DEFAULT, out.data()) < 0)
    fail(path, "cannot read rows");
  return out;
}

// ---- string datasets ----------------------------------------------------------------------

void H5File::write_strings(std::string_view path, const std::vector<std::string>& values, H5StringKind kind) {
  require_writable(path);
  if (exists(path)) fail(path, "cannot create dataset: an object of that name exists");
  const ErrorSilencer quiet;
  std::size_t longest = 0;
  for (const auto& v : values) longest = std::max(longest, v.size());
  const Handle type = string_type(kind, longest);
  const hsize_t n = values.size();
  Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  const Handle lcpl = intermediate_groups_lcpl();
  Handle ds(H5Dcreate2(id_, object_name(path).c_str(), type.get(), space.get(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT),
            H5Dclose);
  if (!ds.valid()) fail(path, "cannot create string dataset");
  if (values.empty()) return;
  herr_t rc;
  if (kind == H5StringKind::Variable) {
    std::vector<const char*> ptrs;
    for (const auto& v : values) ptrs.push_back(v.c_str());
    rc = H5Dwrite(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data());
  } else {
    const std::size_t size = std::max<std::size_t>(longest, 1);
    std::vector<char> buffer(values.size() * size, '\0');
    for (std::size_t i = 0; i < values.size(); ++i) std::copy(values[i].begin(), values[i].end(), &buffer[i * size]);
    rc = H5Dwrite(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data());
  }
  if (rc < 0) fail(path, "cannot write string dataset");
}

std::vector<std::string> H5File::read_strings(std::string_view path) const {
  require_open();
  const ErrorSilencer quiet;
  Handle ds(H5Dopen2(id_, object_name(path).c_str(), H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) fail(path, "cannot open dataset to read strings");
  Handle type(H5Dget_type(ds.get()), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_STRING) fail(path, "dataset does not hold strings");
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0) fail(path, "cannot query dataspace");
  std::vector<std::string> out;
  if (n == 0) return out;
  if (!plausible_allocation(id_, {static_cast<hsize_t>(n)}, std::max<std::size_t>(H5Tget_size(type.get()), 1)))
    fail(path, std::to_string(n) + " strings are more than the file can hold (damaged file?)");
  auto read = [&](hid_t mem, void* buf) { return H5Dread(ds.get(), mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf); };
  if (!read_string_values(type.get(), space.get(), static_cast<hsize_t>(n), read, out)) fail(path, "cannot read strings");
  return out;
}

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
Handle open_for_new_attribute(hid_t file, const std::string& object, const std::string& name) {
  Handle obj(H5Oopen(file, object.c_str(), H5P_DEFAULT), H5Oclose);
  if (obj.valid() && H5Aexists(obj.get(), name.c_str()) > 0) H5Adelete(obj.get(), name.c_str());
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
    static_cast<std::vector<std::string>*>(data)->emplace_back(n);
    return 0;
  };
  hsize_t index = 0;
  if (H5Aiterate2(obj.get(), H5_INDEX_NAME, H5_ITER_INC, &index, collect, &names) < 0)
    fail(object, "cannot list attributes");
  return names;
}

#undef DC_OPEN_DATASET
#undef DC_OPEN_ATTRIBUTE

// ---- explicit instantiations ----------------------------------------------------------------

#define DC_H5_INSTANTIATE(T)                                                                                     \
  template void H5File::create_dataset<T>(std::string_view, const H5Shape&, const H5DatasetOptions&);           \
  template void H5File::write<T>(std::string_view, std::span<const T>, const H5Shape&, const H5DatasetOptions&); \
  template hsize_t H5File::append_rows<T>(std::string_view, std::span<const T>);                                 \
  template void H5File::write_rows<T>(std::string_view, hsize_t, std::span<const T>);                           \
  template std::vector<T> H5File::read<T>(std::string_view) const;                                               \
  template std::vector<T> H5File::read<T>(std::string_view, const H5Shape&) const;                               \
  template std::vector<T> H5File::read_rows<T>(std::string_view, hsize_t, hsize_t) const;                        \
  template void H5File::set_attribute<T>(std::string_view, std::string_view, T);                                 \
  template void H5File::set_attribute_array<T>(std::string_view, std::string_view, std::span<const T>);          \
  template T H5File::attribute<T>(std::string_view, std::string_view) const;                                     \
  template std::vector<T> H5File::attribute_array<T>(std::string_view, std::string_view) const;

DC_H5_INSTANTIATE(double)
DC_H5_INSTANTIATE(float)
DC_H5_INSTANTIATE(std::int32_t)
DC_H5_INSTANTIATE(std::int64_t)
DC_H5_INSTANTIATE(std::uint8_t)
#undef DC_H5_INSTANTIATE

std::int64_t h5_open_object_count() {
  const ErrorSilencer quiet;
  const ssize_t n = H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL);
  if (n < 0) throw IoError(with_reason("HDF5: cannot count the open objects"));
  return static_cast<std::int64_t>(n);
}

// ---- AtomicH5File -------------------------------------------------------------------------

H5File H5File::create_in_memory(const std::string& label) {
  const ErrorSilencer quiet;
  const Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  // Grow the image in 1 MiB steps; backing_store = 0: HDF5 never touches the disk.
  if (!fapl.valid() || H5Pset_fapl_core(fapl.get(), std::size_t{1} << 20, 0) < 0)
    throw IoError(label + ": " + with_reason("cannot set up an in-memory HDF5 file"));
  const hid_t id = H5Fcreate(label.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get());
  if (id < 0) throw IoError(label + ": " + with_reason("cannot create an in-memory HDF5 file"));
  return H5File(label, id, true);
}

std::string H5File::file_image() {
  require_open();
  const ErrorSilencer quiet;
  if (H5Fflush(id_, H5F_SCOPE_GLOBAL) < 0) fail("/", "flush failed");  // the image is what is on "disk"
  const ssize_t size = H5Fget_file_image(id_, nullptr, 0);
  if (size < 0) fail("/", "cannot take the file image");
  std::string image(static_cast<std::size_t>(size), '\0');
  if (size > 0 && H5Fget_file_image(id_, image.data(), image.size()) != size) fail("/", "cannot take the file image");
  return image;
}

AtomicH5File::AtomicH5File(std::string path)
    : path_(std::move(path)), tmp_(path_ + ".tmp"), file_(H5File::create_in_memory(path_)) {}

AtomicH5File::~AtomicH5File() = default;  // an uncommitted file only ever existed in memory

H5File& AtomicH5File::file() {
  if (committed_ || !file_) throw InvalidArgument(path_ + ": atomic HDF5 file already committed");
  return *file_;
}

void AtomicH5File::commit() {
  H5File& f = file();
  const std::string image = f.file_image();
  f.close();
  file_.reset();
  write_file_atomically(path_, image);  // tmp_ + rename; removes tmp_ on failure
  committed_ = true;
}

}  // namespace dc
