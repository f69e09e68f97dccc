// RAII layer on the HDF5 C API (see h5.hpp for the conventions): file lifetime, objects,
// numeric and string datasets. Attributes: h5_attributes.cpp; AtomicH5File: atomic_h5_file.cpp.
//
// Every public member starts with an ErrorSilencer (HDF5 must not print its error stack
// to stderr; we turn failures into one-line IoErrors instead) and closes every id it
// opens through Handle, so no HDF5 object outlives the call that opened it — that keeps
// H5Fclose's default "weak" close degree from ever leaving a file silently open.
#include "dc/io/h5.hpp"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <numeric>
#include <utility>

#include "dc/core/error.hpp"
#include "h5_detail.hpp"
#include "h5_file_hash.hpp"

namespace dc {

// h5.hpp declares HDF5's two integer types itself so that it need not include <hdf5.h>.
static_assert(std::is_same_v<dc::hsize_t, ::hsize_t>, "dc::hsize_t must be HDF5's hsize_t");
static_assert(std::is_same_v<std::int64_t, ::hid_t>, "H5File::Id (std::int64_t) must be HDF5's hid_t");

using namespace h5_detail;

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
  const bool io = writable_ && id_ >= 0 && write_failed_on_stack();
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
  const Handle fapl = file_access_with_checksums();
  if (!fapl.valid()) throw IoError(path + ": " + with_reason("cannot set up the HDF5 file format"));
  const Handle fcpl = file_creation();
  const hid_t id = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get());
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
  // A sealed file (a data set manifest) is checked whole before libhdf5 reads a byte of it:
  // some damage crashes libhdf5 itself (h5_file_hash.hpp).
  if (writable) drop_file_hash(path);
  else verify_file_hash(path);
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
  const Handle gcpl = group_creation();
  if (!create_parent_groups(id_, object_name(path))) fail(path, "cannot create the parent groups");
  Handle g(H5Gcreate2(id_, object_name(path).c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), H5Gclose);
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
  const std::string checksum = attribute_checksum_name(name);
  if (H5Aexists_by_name(id_, object_name(object).c_str(), checksum.c_str(), H5P_DEFAULT) > 0)
    (void)H5Adelete_by_name(id_, object_name(object).c_str(), checksum.c_str(), H5P_DEFAULT);
}

// ---- numeric datasets ---------------------------------------------------------------------

namespace {

/// Dataset-creation properties: how a dataset of `shape` is laid out so that every stored
/// byte is checked on read (h5_checksum.hpp). Datasets with elements are chunked — whole rows
/// per chunk, ≈ 256 KiB unless options.chunk_rows says otherwise, so appends and row reads
/// touch few chunks and compression stays effective — with Fletcher-32 as the last filter
/// (after shuffle + deflate: it checks the bytes on disk). Scalars and empty fixed-size
/// datasets cannot be chunked; they are compact: their data lives in the object header,
/// which carries its own checksum. Invalid handle on failure.
template <H5Element T>
Handle dataset_layout(const H5Shape& shape, const H5DatasetOptions& options) {
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (!dcpl.valid()) return dcpl;
  if (shape.empty() || (!options.extendible && product(shape) == 0)) {
    if (H5Pset_layout(dcpl.get(), H5D_COMPACT) < 0 || !keep_links_and_attributes_compact(dcpl.get(), false))
      dcpl.reset();
    return dcpl;
  }
  H5Shape chunk(shape.size());
  for (std::size_t i = 1; i < shape.size(); ++i) chunk[i] = std::max<hsize_t>(shape[i], 1);
  if (options.extendible_columns) chunk[1] = std::max<hsize_t>(shape[1], 64);
  const hsize_t row_bytes = product(chunk, 1) * sizeof(T);
  hsize_t rows = options.chunk_rows;
  if (rows == 0) {
    rows = std::max<hsize_t>(1, (hsize_t{256} << 10) / row_bytes);
    if (!options.extendible) rows = std::min(rows, std::max<hsize_t>(shape[0], 1));
  }
  chunk[0] = rows;
  if constexpr (std::is_floating_point_v<T>) {  // cells of added columns never written read as NaN
    const T nan = std::numeric_limits<T>::quiet_NaN();
    if (options.extendible_columns && H5Pset_fill_value(dcpl.get(), memory_type(type_of<T>()), &nan) < 0) {
      dcpl.reset();
      return dcpl;
    }
  }
  const bool ok = H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()) >= 0 &&
                  (options.deflate == 0 || (H5Pset_shuffle(dcpl.get()) >= 0 &&
                                            H5Pset_deflate(dcpl.get(), static_cast<unsigned>(options.deflate)) >= 0)) &&
                  H5Pset_fletcher32(dcpl.get()) >= 0;
  if (!ok || !keep_links_and_attributes_compact(dcpl.get(), false)) dcpl.reset();
  return dcpl;
}

}  // namespace

template <H5Element T>
void H5File::create_dataset(std::string_view path, const H5Shape& shape, const H5DatasetOptions& options) {
  require_writable(path);
  if (options.deflate < 0 || options.deflate > 9)
    throw InvalidArgument(path_ + ": " + object_name(path) + ": deflate level must be in 0..9");
  if ((options.extendible || options.deflate > 0) && shape.empty())
    throw InvalidArgument(path_ + ": " + object_name(path) + ": a scalar dataset cannot be extendible or compressed");
  if (exists(path)) fail(path, "cannot create dataset: an object of that name exists");

  const ErrorSilencer quiet;
  if (options.extendible_columns && (!options.extendible || shape.size() < 2))
    throw InvalidArgument(path_ + ": " + object_name(path) + ": extendible columns need an extendible dataset of rank >= 2");
  H5Shape maxdims = shape;
  if (options.extendible) maxdims[0] = H5S_UNLIMITED;
  if (options.extendible_columns) maxdims[1] = H5S_UNLIMITED;
  Handle space(shape.empty() ? H5Screate(H5S_SCALAR)
                             : H5Screate_simple(static_cast<int>(shape.size()), shape.data(), maxdims.data()),
               H5Sclose);
  if (!space.valid()) fail(path, "cannot create dataspace " + to_string(shape));

  const Handle dcpl = dataset_layout<T>(shape, options);
  if (!dcpl.valid()) fail(path, "cannot set up the chunk shape, compression and checksum");
  if (!create_parent_groups(id_, object_name(path))) fail(path, "cannot create the parent groups");
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
  /// A virtual dataset (create_virtual): its data is in other files, so the size of this
  /// file says nothing about a plausible extent.
  bool virtual_layout = false;
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
  Handle dcpl(H5Dget_create_plist(d.ds.get()), H5Pclose);
  d.virtual_layout = dcpl.valid() && H5Pget_layout(dcpl.get()) == H5D_VIRTUAL;
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
  if (!ds.valid() || H5Dwrite(ds.get(), memory_type(type_of<T>()), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0 ||
      ds.close() < 0)  // the chunk cache is written at the close
    fail(path, "cannot write dataset");
}

namespace {
/// Writes `data` into rows [first, first + rows) of an open dataset; on failure calls
/// `on_error` (which throws) while the dataspaces are still open: closing them is an HDF5
/// call, which would clear the error stack that says whether the write hit the disk's limit
/// (H5File::fail abandons the file then, before any flush can fail).
template <class OnError>
void write_row_block(hid_t ds, const H5Shape& dims, hsize_t first, hsize_t rows, hid_t mem_type, const void* data,
                     const OnError& on_error) {
  Handle file_space(H5Dget_space(ds), H5Sclose);
  H5Shape start(dims.size(), 0), count = dims;
  start[0] = first;
  count[0] = rows;
  Handle mem_space(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr), H5Sclose);
  if (!file_space.valid() || !mem_space.valid() ||
      H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr) < 0 ||
      H5Dwrite(ds, mem_type, mem_space.get(), file_space.get(), H5P_DEFAULT, data) < 0)
    on_error();
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
  write_row_block(d.ds.get(), grown, d.dims[0], rows, memory_type(type_of<T>()), data.data(),
                  [&] { fail(path, "cannot write appended rows"); });
  if (d.ds.close() < 0) fail(path, "cannot write appended rows");  // the chunk cache is written here
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
  if (rows > 0)
    write_row_block(d.ds.get(), d.dims, first_row, rows, memory_type(type_of<T>()), data.data(),
                    [&] { fail(path, "cannot write rows"); });
  if (d.ds.close() < 0) fail(path, "cannot write rows");  // the chunk cache is written here
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

void H5File::resize(std::string_view path, const H5Shape& dims) {
  require_writable(path);
  const ErrorSilencer quiet;
  DC_OPEN_DATASET(d, path, "resize");
  if (dims.size() != d.dims.size()) fail(path, "cannot resize to " + to_string(dims) + ": another rank");
  for (std::size_t i = 0; i < dims.size(); ++i)
    if (d.maxdims[i] != H5S_UNLIMITED && dims[i] > d.maxdims[i])
      fail(path, "cannot resize to " + to_string(dims) + ": axis " + std::to_string(i) + " is not extendible");
  if (H5Dset_extent(d.ds.get(), dims.data()) < 0) fail(path, "cannot resize dataset to " + to_string(dims));
}

H5Shape H5File::shape(std::string_view path) const {
  require_open();
  const ErrorSilencer quiet;
  DC_OPEN_DATASET(d, path, "query its shape");
  return d.dims;
}

hsize_t H5File::rows(std::string_view path) const {
  const H5Shape dims = shape(path);
  if (dims.empty()) fail(path, "dataset is a scalar, expected rows");
  return dims[0];
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
  if (!countable(d.dims, sizeof(T)) || (!d.virtual_layout && !plausible_allocation(id_, d.dims, sizeof(T))))
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
  if (!countable(block, sizeof(T)) || (!d.virtual_layout && !plausible_allocation(id_, block, sizeof(T))))
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
  // Fixed-length strings like numeric data: chunked with Fletcher-32 (≤ 256 KiB chunks), or
  // compact when empty, so that every stored byte is covered by a checksum.
  const std::size_t element = std::max<std::size_t>(longest, 1);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  const hsize_t chunk = std::max<hsize_t>(1, std::min<hsize_t>(n, (hsize_t{256} << 10) / element));
  // (HDF5 filters cannot take variable-length data: those keep the default layout, and the
  // stored hash covers their values.)
  const bool layout_ok = dcpl.valid() && (kind == H5StringKind::Variable ||
                                          (n == 0 ? H5Pset_layout(dcpl.get(), H5D_COMPACT) >= 0
                                                  : H5Pset_chunk(dcpl.get(), 1, &chunk) >= 0 &&
                                                        H5Pset_fletcher32(dcpl.get()) >= 0));
  if (!layout_ok || !keep_links_and_attributes_compact(dcpl.get(), false))
    fail(path, "cannot set up the string dataset's chunks and checksum");
  if (!create_parent_groups(id_, object_name(path))) fail(path, "cannot create the parent groups");
  Handle ds(H5Dcreate2(id_, object_name(path).c_str(), type.get(), space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
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
  if (rc < 0 || ds.close() < 0) fail(path, "cannot write string dataset");
  // Variable-length strings' bytes are in the global heap, which HDF5 does not checksum: store
  // a hash of them in the (checksummed) object header.
  if (kind == H5StringKind::Variable) set_attribute<std::int64_t>(path, kStringsChecksum, strings_checksum(values));
}

void H5File::verify_strings(Id object, std::string_view path, const std::vector<std::string>& values,
                            std::string_view attribute) const {
  const std::string name = attribute.empty() ? std::string(kStringsChecksum) : attribute_checksum_name(attribute);
  const htri_t stored = H5Aexists(object, name.c_str());
  if (stored == 0) return;  // written without a checksum (an older file, h5py): read unchecked
  std::int64_t expected = 0;
  Handle attr(stored > 0 ? H5Aopen(object, name.c_str(), H5P_DEFAULT) : -1, H5Aclose);
  if (!attr.valid() || H5Aread(attr.get(), H5T_NATIVE_INT64, &expected) < 0)
    fail(path, with_reason("cannot read the checksum attribute " + name));
  if (expected != strings_checksum(values)) {
    fail(path, std::string("checksum mismatch: the file is damaged (") +
                   (attribute.empty() ? "the strings" : "attribute '" + std::string(attribute) + "'") +
                   " do not match their stored checksum)");
  }
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
  if (n == 0) {
    verify_strings(ds.get(), path, out);
    return out;
  }
  if (!plausible_allocation(id_, {static_cast<hsize_t>(n)}, std::max<std::size_t>(H5Tget_size(type.get()), 1)))
    fail(path, std::to_string(n) + " strings are more than the file can hold (damaged file?)");
  auto read = [&](hid_t mem, void* buf) { return H5Dread(ds.get(), mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf); };
  if (!read_string_values(type.get(), space.get(), static_cast<hsize_t>(n), read, out)) fail(path, "cannot read strings");
  verify_strings(ds.get(), path, out);
  return out;
}

#undef DC_OPEN_DATASET

// ---- explicit instantiations (the attribute members: h5_attributes.cpp) -------------------

#define DC_H5_INSTANTIATE(T)                                                                                     \
  template void H5File::create_dataset<T>(std::string_view, const H5Shape&, const H5DatasetOptions&);           \
  template void H5File::write<T>(std::string_view, std::span<const T>, const H5Shape&, const H5DatasetOptions&); \
  template hsize_t H5File::append_rows<T>(std::string_view, std::span<const T>);                                 \
  template void H5File::write_rows<T>(std::string_view, hsize_t, std::span<const T>);                           \
  template std::vector<T> H5File::read<T>(std::string_view) const;                                               \
  template std::vector<T> H5File::read<T>(std::string_view, const H5Shape&) const;                               \
  template std::vector<T> H5File::read_rows<T>(std::string_view, hsize_t, hsize_t) const;

DC_H5_INSTANTIATE(double)
DC_H5_INSTANTIATE(float)
DC_H5_INSTANTIATE(std::int32_t)
DC_H5_INSTANTIATE(std::int64_t)
DC_H5_INSTANTIATE(std::uint8_t)
#undef DC_H5_INSTANTIATE

std::int64_t h5_open_object_count() {
  const ErrorSilencer quiet;
  // Not H5F_OBJ_DATATYPE: this layer commits no named datatypes, and with some builds of the
  // same libhdf5 (our ASan build) the library's ~125 predefined types are counted as well.
  const ssize_t n =
      H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_FILE | H5F_OBJ_DATASET | H5F_OBJ_GROUP | H5F_OBJ_ATTR);
  if (n < 0) throw IoError(with_reason("HDF5: cannot count the open objects"));
  return static_cast<std::int64_t>(n);
}

}  // namespace dc
