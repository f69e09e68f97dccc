// libFuzzer harness: the FCLIB local-problem reader (dc::read_fclib_local, HDF5).
//
// HDF5 reads files by name, so the bytes go to a per-process temporary file first.
// Properties: read_fclib_local returns or throws IoError (its one-line errors); what it
// returns is consistent (compressed columns within range, q of 2nc and μ of nc entries,
// finite, μ ≥ 0) and writes back and reads back equal.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "dc/core/error.hpp"
#include "dc/lcp/fclib_file.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static dc::fuzz::TempInputFile file(".fclib.hdf5");
  static dc::fuzz::TempInputFile back(".fclib-back.hdf5");
  const std::string& path = file.write(data, size);
  dc::FclibLocalProblem p;
  try {
    p = dc::read_fclib_local(path);
  } catch (const dc::IoError&) {
    return 0;
  }
  const auto rows = static_cast<std::size_t>(p.rows);
  if (p.col_start.size() != rows + 1 || p.q.size() != rows || p.mu.size() != rows / 2 ||
      static_cast<std::size_t>(p.col_start.back()) != p.values.size() || p.row_index.size() != p.values.size())
    dc::fuzz::property_failed("read_fclib_local returned inconsistent sizes");
  for (double m : p.mu)
    if (!(m >= 0) || !std::isfinite(m)) dc::fuzz::property_failed("read_fclib_local returned a bad mu");
  try {
    dc::write_fclib_local(back.path(), p);
    const dc::FclibLocalProblem again = dc::read_fclib_local(back.path());
    if (again.values != p.values || again.row_index != p.row_index || again.q != p.q || again.mu != p.mu)
      dc::fuzz::property_failed("an FCLIB problem does not read back equal");
  } catch (const dc::InvalidArgument&) {
    dc::fuzz::property_failed("write_fclib_local refused a problem read_fclib_local accepted");
  }
  return 0;
}
