#pragma once
// A small RAII layer on the HDF5 C API for every HDF5 writer and reader of the project (layouts
// and conventions: docs/formats.md "HDF5 conventions"). Paths are absolute (missing groups are
// created); elements are double, float, int32, int64 or uint8, little-endian, row-major; writes
// store exactly T, reads accept types that convert to T without loss; shape {} is a scalar, an
// extendible dataset has an unlimited, chunked first axis grown by append_rows().
// Errors: a failing HDF5 call throws dc::IoError with one line naming the file, the object path
// and the operation (plus HDF5's innermost reason); caller contract violations (buffer size ≠
// product of the shape, compression level outside 0..9, a closed file) throw dc::InvalidArgument.
// HDF5's error-stack printing is off during each call of this layer (scope guard, per thread in
// Debian's thread-safe libhdf5). Objects are not synchronised: one H5File per thread.
// dc_io links HDF5 PRIVATE: no <hdf5.h> here; an open file is an opaque id (h5.cpp checks that
// hsize_t and hid_t match the types declared here).
#include <concepts>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace dc {

/// The element types the helper reads and writes.
template <class T>
concept H5Element = std::same_as<T, double> || std::same_as<T, float> || std::same_as<T, std::int32_t> ||
                    std::same_as<T, std::int64_t> || std::same_as<T, std::uint8_t>;

/// Stored element type of a dataset or attribute.
enum class H5Type { Float64, Float32, Int32, Int64, UInt8 };

/// "float64", "float32", "int32", "int64", "uint8" (numpy's names).
const char* to_string(H5Type t);

/// An extent, row index or row count: HDF5's `hsize_t` (unsigned 64-bit), declared here under
/// the same name so that code using this layer reads like HDF5 code without <hdf5.h>.
using hsize_t = unsigned long long;

using H5Shape = std::vector<hsize_t>;

/// Wildcard extent in an expected shape: {kH5Any, n, 2} accepts any number of rows.
inline constexpr hsize_t kH5Any = ~hsize_t{0};

/// "(3,5,2)"; kH5Any prints as "*", a scalar as "()".
std::string to_string(const H5Shape& shape);

/// How a dataset is laid out on disk.
struct H5DatasetOptions {
  /// Unlimited first axis, so append_rows()/resize_rows() can grow it. Implies chunking.
  bool extendible = false;
  /// Rows (first-axis extent) per chunk; 0 = automatic (≈ 256 KiB chunks). Chunking is
  /// used only when extendible or compressed; the other axes are never split.
  hsize_t chunk_rows = 0;
  /// gzip (deflate) level 1–9 with the byte-shuffle filter in front; 0 = uncompressed.
  int deflate = 0;
  /// Also the second axis is unlimited (needs extendible and rank ≥ 2): resize() can widen
  /// the dataset, e.g. a trajectory's (step, body) states when bodies enter during a run.
  /// Chunks then span max(extent, 64) columns, and cells never written read as the fill
  /// value: NaN for float32/float64, 0 otherwise.
  bool extendible_columns = false;
};

/// One source of a virtual dataset (H5File::create_virtual): all rows of `dataset` in `file`.
struct H5VirtualSource {
  /// The source file, relative to the directory of the file holding the virtual dataset
  /// (HDF5 resolves it there, also for h5py) or absolute.
  std::string file;
  std::string dataset;  ///< object path in `file`
  hsize_t rows = 0;     ///< its first-axis extent (the other axes are the virtual dataset's)
};

/// How strings are stored: fixed-length, NUL-padded (numpy `S<n>`, h5py gives `bytes`; the
/// default) or variable-length (h5py `str`). Reads accept both. Variable-length strings live
/// in HDF5's global heap, which has no checksum (this layer stores a hash next to them) and
/// whose damage crashes libhdf5 1.10.8 in H5HG_read before any check can run; fixed-length
/// ones sit in checksummed object headers or chunks — so this layer writes those by default.
enum class H5StringKind { Variable, Fixed };

/// An open HDF5 file. Move-only; the destructor closes it (errors ignored — call close()
/// to see them). All object paths are relative to the root group.
///
///   auto out = dc::AtomicH5File("results.h5");            // built in memory
///   out->write<double>("/bodies/position", xs, {steps, n, 2});
///   out->create_dataset<float>("/samples/lambda", {0, 64}, {.extendible = true, .deflate = 4});
///   out->append_rows<float>("/samples/lambda", row);       // grows the first axis
///   out.commit();                                          // results.h5.tmp, renamed → results.h5
///   const auto in = dc::H5File::open_read("results.h5");
///   auto xs = in.read<double>("/bodies/position", {dc::kH5Any, n, 2});  // checks the shape
///
/// Full disk: when a write of a writable file fails at the system level (ENOSPC, EFBIG),
/// the IoError is thrown and the file is abandoned — its descriptor is moved to an anonymous
/// memfd, so that libhdf5 1.10.8, which cannot otherwise close such a file (and crashes at
/// exit on it), can close it. The file on disk then stays as a crash at that moment would
/// leave it; later writes through this object are discarded.
class H5File {
 public:
  /// Creates `path`, truncating an existing file.
  static H5File create(const std::string& path);
  /// Opens an existing file read-only. Missing, non-HDF5 or truncated files → IoError.
  static H5File open_read(const std::string& path);
  /// Opens an existing file for reading and writing (e.g. to append rows and resume).
  static H5File open_rw(const std::string& path);

  H5File(H5File&& other) noexcept;
  H5File& operator=(H5File&& other) noexcept;
  H5File(const H5File&) = delete;
  H5File& operator=(const H5File&) = delete;
  ~H5File();

  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] bool is_open() const { return id_ >= 0; }
  [[nodiscard]] bool writable() const { return writable_; }

  /// Writes all buffered data to disk (H5Fflush, global scope).
  void flush();
  /// Closes the file; later calls (other than close) throw InvalidArgument.
  void close();

  // ---- groups and objects --------------------------------------------------------------
  /// True if a group or dataset exists at `path` (false also when a parent is missing).
  [[nodiscard]] bool exists(std::string_view path) const;
  [[nodiscard]] bool is_group(std::string_view path) const;
  [[nodiscard]] bool is_dataset(std::string_view path) const;
  /// Creates the group and any missing parents; an existing group is fine.
  void create_group(std::string_view path);
  /// Names of the direct children of a group, in name order.
  [[nodiscard]] std::vector<std::string> children(std::string_view group) const;
  /// Unlinks a group or dataset (e.g. to replace it). The space is not reclaimed in place.
  void remove(std::string_view path);
  /// IoError naming `path` unless its object is stored in this file: reached through an
  /// external link (another file), a virtual dataset (rows mapped from other files) or a
  /// dataset with external raw storage are refused. HDF5 reads a missing source of these as
  /// the fill value (zeros) without an error, so a reader that must not accept substitutes
  /// (a problem file, copy_h5_file) checks every object first. An absent object (no
  /// external link on its path) passes: the caller's read says it is missing.
  void require_in_file(std::string_view path) const;

  // ---- numeric datasets ----------------------------------------------------------------
  /// Creates a dataset of T with the given shape (rows may be 0 when extendible). An
  /// existing object at `path` is an error: remove() it first to replace it.
  template <H5Element T>
  void create_dataset(std::string_view path, const H5Shape& shape, const H5DatasetOptions& options = {});
  /// create_dataset + write all of `data` (row-major, size = product of `shape`).
  template <H5Element T>
  void write(std::string_view path, std::span<const T> data, const H5Shape& shape,
             const H5DatasetOptions& options = {});
  template <H5Element T>
  void write(std::string_view path, const std::vector<T>& data, const H5Shape& shape,
             const H5DatasetOptions& options = {}) {
    write<T>(path, std::span<const T>(data), shape, options);
  }
  /// Appends whole rows to an extendible dataset: `data.size()` must be a multiple of the
  /// row size (product of the shape without its first axis). Returns the new row count.
  template <H5Element T>
  hsize_t append_rows(std::string_view path, std::span<const T> data);
  template <H5Element T>
  hsize_t append_rows(std::string_view path, const std::vector<T>& data) {
    return append_rows<T>(path, std::span<const T>(data));
  }
  /// Overwrites rows [first_row, first_row + data.size()/row size) of an existing dataset.
  template <H5Element T>
  void write_rows(std::string_view path, hsize_t first_row, std::span<const T> data);
  /// Creates a virtual dataset (HDF5 ≥ 1.10 VDS) of T: the rows of `sources`, concatenated
  /// in order along the first axis, each of shape `row_shape`. Readers (this layer, h5py)
  /// see one dataset; the data stays in the source files, which must be present when it is
  /// read (HDF5 returns the fill value — NaN for floating point — for a missing one, so
  /// check them first). Without rows, an ordinary empty dataset is created.
  template <H5Element T>
  void create_virtual(std::string_view path, const H5Shape& row_shape, const std::vector<H5VirtualSource>& sources);
  /// Sets the first-axis extent of an extendible dataset (shrinking drops rows: resume
  /// after a crash by cutting back to the last consistent row).
  void resize_rows(std::string_view path, hsize_t rows);
  /// Sets every extent of a dataset (each within its maximum: an extendible dataset's first
  /// axis, and its second with extendible_columns). Same rank as the dataset.
  void resize(std::string_view path, const H5Shape& dims);

  [[nodiscard]] H5Shape shape(std::string_view path) const;
  /// Extent of the dataset's first axis (its rows); IoError for a scalar dataset, which has no
  /// rows (a damaged file can turn a column into one).
  [[nodiscard]] hsize_t rows(std::string_view path) const;
  [[nodiscard]] H5Type type(std::string_view path) const;
  /// IoError unless the dataset's shape matches `expected` (kH5Any matches any extent).
  void require_shape(std::string_view path, const H5Shape& expected) const;

  /// The whole dataset, row-major.
  template <H5Element T>
  [[nodiscard]] std::vector<T> read(std::string_view path) const;
  /// The whole dataset after require_shape(path, expected).
  template <H5Element T>
  [[nodiscard]] std::vector<T> read(std::string_view path, const H5Shape& expected) const;
  /// Rows [first_row, first_row + count) (a hyperslab along the first axis), row-major.
  template <H5Element T>
  [[nodiscard]] std::vector<T> read_rows(std::string_view path, hsize_t first_row, hsize_t count) const;

  // ---- string datasets (1-D) -----------------------------------------------------------
  void write_strings(std::string_view path, const std::vector<std::string>& values,
                     H5StringKind kind = H5StringKind::Fixed);
  [[nodiscard]] std::vector<std::string> read_strings(std::string_view path) const;

  // ---- attributes on "/" (the file), a group or a dataset --------------------------------
  [[nodiscard]] bool has_attribute(std::string_view object, std::string_view name) const;
  /// Creates or replaces a string attribute (UTF-8).
  void set_attribute(std::string_view object, std::string_view name, std::string_view value,
                     H5StringKind kind = H5StringKind::Fixed);
  void set_attribute(std::string_view object, std::string_view name, const char* value,
                     H5StringKind kind = H5StringKind::Fixed) {
    set_attribute(object, name, std::string_view(value), kind);
  }
  /// Creates or replaces a scalar numeric attribute.
  template <H5Element T>
  void set_attribute(std::string_view object, std::string_view name, T value);
  /// Creates or replaces a 1-D numeric attribute.
  template <H5Element T>
  void set_attribute_array(std::string_view object, std::string_view name, std::span<const T> values);
  [[nodiscard]] std::string attribute_string(std::string_view object, std::string_view name) const;
  /// A scalar (or one-element) numeric attribute.
  template <H5Element T>
  [[nodiscard]] T attribute(std::string_view object, std::string_view name) const;
  template <H5Element T>
  [[nodiscard]] std::vector<T> attribute_array(std::string_view object, std::string_view name) const;
  /// Deletes an attribute; IoError if the object or the attribute does not exist.
  void remove_attribute(std::string_view object, std::string_view name);
  /// Names of the attributes of an object.
  [[nodiscard]] std::vector<std::string> attribute_names(std::string_view object) const;

 private:
  /// HDF5's hid_t (an int64_t since HDF5 1.10); -1 when closed.
  using Id = std::int64_t;

  H5File(std::string path, Id id, bool writable);
  static H5File open(const std::string& path, bool writable);
  void require_open() const;
  void require_writable(std::string_view object) const;
  [[noreturn]] void fail(std::string_view object, const std::string& what) const;
  /// IoError "checksum mismatch" unless `values`, read from the open dataset or object
  /// `object` at `path` (the dataset itself, or its string attribute `attribute`), match the
  /// hash stored next to them (io/src/h5_checksum.hpp); nothing to check when none is stored.
  void verify_strings(Id object, std::string_view path, const std::vector<std::string>& values,
                      std::string_view attribute = {}) const;
  /// For AtomicH5File: a new file held in memory only, and the bytes of such a file.
  friend class AtomicH5File;
  static H5File create_in_memory(const std::string& label);
  [[nodiscard]] std::string file_image();

  std::string path_;
  Id id_ = -1;
  bool writable_ = false;
};

/// A file that appears under `path` complete or not at all. It is built in memory (HDF5's
/// core driver, no backing store); commit() takes the finished image and writes it with
/// dc::write_file_atomically (to `path + ".tmp"`, then renamed onto `path`), so readers never
/// see a half-written file and a crash or a full disk leaves the old `path` intact.
/// Building in memory also keeps failing disk writes out of libhdf5: 1.10.8 cannot close a
/// file whose writes failed (H5Fclose fails and the id dangles; the library's own cleanup at
/// exit then crashes). Costs the file's size in memory until commit(). Destroying it
/// without commit() discards everything. Two writers of the same path at once are not
/// supported (they would share the temporary name).
class AtomicH5File {
 public:
  /// Starts an empty file in memory; nothing is written to disk before commit().
  explicit AtomicH5File(std::string path);
  AtomicH5File(const AtomicH5File&) = delete;
  AtomicH5File& operator=(const AtomicH5File&) = delete;
  ~AtomicH5File();

  /// The file being written; InvalidArgument after commit().
  H5File& file();
  H5File* operator->() { return &file(); }
  /// Writes the finished file to `path.tmp` and renames it onto `path` (replacing an existing
  /// file). On IoError (e.g. disk full) `path` is unchanged and no temporary is left.
  void commit();
  /// Seals the file at commit with a hash of all its bytes, verified by every open before
  /// libhdf5 reads it (for files whose damage libhdf5 cannot survive, e.g. virtual datasets'
  /// mappings; readers without the check, such as h5py, read it as an unsealed file). Costs one
  /// pass over the file per open: for small files.
  void add_whole_file_hash() { whole_file_hash_ = true; }

  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] const std::string& tmp_path() const { return tmp_; }
  [[nodiscard]] bool committed() const { return committed_; }

 private:
  std::string path_;
  std::string tmp_;
  std::optional<H5File> file_;
  bool committed_ = false;
  bool whole_file_hash_ = false;
};

/// Number of HDF5 objects (files, groups, datasets, attributes) open in this process right
/// now: H5Fget_obj_count(H5F_OBJ_ALL, FILE | DATASET | GROUP | ATTR). Every H5File call
/// closes what it opens, so with no H5File open this is 0; tests use it to prove that a
/// reader's error path leaked nothing (a leaked id keeps its file open and makes HDF5 print
/// "infinite loop closing library" at exit).
[[nodiscard]] std::int64_t h5_open_object_count();

/// For a program's main(), before anything else touches HDF5: libhdf5 then registers no
/// exit-time cleanup. Under a file-size limit (EFBIG) a file whose writes failed cannot be
/// closed at all (its close must truncate it to a size past the limit), and libhdf5's own
/// cleanup at exit crashes on the id left open; a program whose files are all closed by their
/// owners before main returns needs no such cleanup. Returns false if HDF5 was already in use.
bool h5_skip_exit_cleanup();

}  // namespace dc
