// deepcontact.copy_hdf5: re-write an HDF5 file through the project's HDF5 layer, e.g. to add
// the checksums files written before them lack (docs/formats.md "Checksums").
#include <filesystem>
#include <system_error>

#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/io/h5_copy.hpp"
#include "py_common.hpp"

namespace dc::py {

void bind_io(pyb::module_& m) {
  m.def(
      "copy_hdf5",
      [](pyb::object source, pyb::object dest) {
        const std::string from = path_string(source), to = path_string(dest);
        pyb::gil_scoped_release release;
        copy_h5_file(from, to);
      },
      pyb::arg("source"), pyb::arg("dest"),
      "Copy every group, dataset and attribute of the HDF5 file `source` to `dest` (written atomically) through "
      "DeepContact's HDF5 layer: values bit-equal, with its per-dataset checksums (Fletcher-32 chunks, "
      "checksummed metadata) and fixed-length strings. Raises IoError (an OSError) naming the object it cannot "
      "copy, or when `source` is damaged.");
  m.def(
      "_commit_file",
      [](pyb::object tmp_path, pyb::object final_path) {
        const std::string tmp = path_string(tmp_path), to = path_string(final_path);
        pyb::gil_scoped_release release;
        try {
          sync_path(tmp);
          durable_rename(tmp, to);
        } catch (const dc::IoError&) {
          std::error_code ignored;
          std::filesystem::remove(tmp, ignored);
          throw;
        }
      },
      pyb::arg("tmp"), pyb::arg("path"),
      "Internal: fsync the complete file `tmp`, rename it onto `path` and fsync the directory "
      "(dc::sync_path, dc::durable_rename); on failure `tmp` is removed and IoError raised.");
}

}  // namespace dc::py
