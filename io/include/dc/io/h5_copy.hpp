#pragma once
// Re-writing an HDF5 file through dc::H5File, e.g. to give a file without checksums (an
// older file, or one written by h5py) the checksums of this layer (docs/formats.md "Checksums").
#include <string>

namespace dc {

/// Copies every group, dataset and attribute of `from` into a new file `to` (written
/// atomically, replacing `to`), through H5File: values bit-equal, element types and shapes
/// kept, extendible datasets still extendible, a gzip level kept; strings become fixed-length
/// (H5StringKind: the global heap of variable-length ones has no checksum), and the layout
/// and Fletcher-32 checksums are this layer's. Reading `from` verifies
/// whatever checksums it already has. Throws IoError naming the object it cannot copy (types
/// this layer does not handle: compound, enum, references, >1 string per attribute, …),
/// and objects whose values are not in `from` (H5File::require_in_file: external links,
/// virtual datasets such as a data set manifest's, external storage).
void copy_h5_file(const std::string& from, const std::string& to);

}  // namespace dc
