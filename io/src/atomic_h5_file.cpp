// AtomicH5File: an HDF5 file built in memory and written to disk at commit (see h5.hpp).
#include <string>
#include <utility>

#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/io/h5.hpp"
#include "h5_detail.hpp"
#include "h5_file_hash.hpp"
#include "h5_superblock.hpp"

namespace dc {

using namespace h5_detail;

H5File H5File::create_in_memory(const std::string& label) {
  const ErrorSilencer quiet;
  const Handle fapl = file_access_with_checksums();
  // Grow the image in 1 MiB steps; backing_store = 0: HDF5 never touches the disk.
  if (!fapl.valid() || H5Pset_fapl_core(fapl.get(), std::size_t{1} << 20, 0) < 0)
    throw IoError(label + ": " + with_reason("cannot set up an in-memory HDF5 file"));
  const Handle fcpl = file_creation();
  const hid_t id = H5Fcreate(label.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get());
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
  fix_superblock_checksum(image);  // the copy's flags were cleared, its checksum was not
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
  std::string image = f.file_image();
  f.close();
  file_.reset();
  if (whole_file_hash_) image = with_file_hash(std::move(image));
  write_file_atomically(path_, image);  // tmp_ + rename; removes tmp_ on failure
  committed_ = true;
}

}  // namespace dc
