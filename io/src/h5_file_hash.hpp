#pragma once
// A hash of a whole HDF5 file's bytes, stored in a 24-byte trailer after HDF5's image
// (docs/formats.md "Checksums"): "DCFHASH1", the image's length (uint64, little-endian), then
// the FNV-1a 64 hash of those bytes. For files whose damage libhdf5 cannot survive: HDF5 keeps a
// virtual dataset's source mappings in its global heap, which carries no checksum, and
// libhdf5 1.10.8 aborts the process on some damaged mappings ("buffer overflow detected" in
// H5S_select_deserialize) when the dataset is opened — so the data set manifest (all virtual
// datasets) is sealed with it and checked before libhdf5 reads a byte. HDF5 ignores bytes
// past its end-of-file address: h5py and readers without the check open a sealed file
// like any other. FNV-1a
// detects any single changed byte (every step is a bijection of the state), i.e. every
// single bit flip, including flips inside the trailer (its length or hash then disagree).
#include <string>

namespace dc::h5_detail {

/// `image` followed by its trailer.
std::string with_file_hash(std::string image);

/// For a file ending in a trailer: IoError "PATH: checksum mismatch: the file is damaged (…)"
/// when the bytes before it do not match the hash (or the recorded length is not the file's).
/// Returns whether the file carries a trailer (false: nothing checked; older or unsealed files).
bool verify_file_hash(const std::string& path);

/// Removes a verified trailer (before the file is opened for writing: HDF5 may then change
/// the bytes, and a stale hash would read as damage). Nothing for a file without one.
void drop_file_hash(const std::string& path);

}  // namespace dc::h5_detail
