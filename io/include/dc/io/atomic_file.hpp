#pragma once
// Writing a small file (JSON, CSV, Markdown) so that readers never see half of it: the bytes
// go to `path + ".tmp"`, which is renamed onto `path` only after every byte was written and
// flushed. On failure (e.g. a full disk: ENOSPC, or EFBIG past a file-size limit) the
// temporary is removed and `path` keeps its earlier content. HDF5 files have the same
// guarantee through dc::AtomicH5File (h5.hpp).
#include <string>
#include <string_view>

namespace dc {

/// Writes `bytes` to `path` atomically (tmp + rename, replacing an existing file). Throws
/// dc::IoError with one line naming the file when it cannot be written or renamed.
void write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace dc
