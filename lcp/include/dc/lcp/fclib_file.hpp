#pragma once
// FCLIB local frictional-contact problems (the HDF5 format of the FCLIB benchmark collection,
// https://frictionalcontactlibrary.github.io; Debian's libfclib 3.1.0 reads and writes the
// same files), spacedim 2 only. Layout (docs/formats.md "FCLIB"):
//
//   /fclib_local/spacedim          int32 (1): 2 (3 is refused: 3D friction)
//   /fclib_local/W/{m,n,nz,nzmax}  int32 (1) each: m = n = 2nc; nz = −1 compressed columns,
//                                  −2 compressed rows, ≥ 0 a triplet list of nz entries
//   /fclib_local/W/p, i            int32: compressed: p = n+1 column (row) starts, i = nzmax
//                                  row (column) indices; triplet: p = column, i = row index
//                                  of each entry (CSparse's convention)
//   /fclib_local/W/x               float64: the values (nzmax, or nz for a triplet list)
//   /fclib_local/vectors/q         float64 (2nc);  /fclib_local/vectors/mu  float64 (nc)
//   /solution/{u,r}                float64 (2nc) each: velocity u = W r + q and reaction r
//   /guesses/number_of_guesses     int32 (1);  /guesses/1, /guesses/2, …: {u, r} as /solution
//
// This reader does not use libfclib: libfclib trusts the sizes stored in the file (it reads a
// dataset into a buffer sized by W/m, W/nz, …, and calls exit(1) on any HDF5 error), so a
// damaged file could overflow its buffers or end the process. Here every size is checked
// against the datasets' shapes before reading, every index against the matrix, every value
// for finiteness; errors are one-line dc::IoError messages "FILE: what". The tests check
// that libfclib reads what this writer writes and the other way round.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dc {

/// Largest W (rows) and stored entries the reader accepts.
inline constexpr std::int64_t kMaxFclibRows = 2000000;
inline constexpr std::int64_t kMaxFclibEntries = 20000000;

/// A solution or a guess of a local problem: reaction r and velocity u = W r + q (2nc each).
struct FclibSolution {
  std::vector<double> r;
  std::vector<double> u;
};

/// A local problem, spacedim 2, W in compressed-column form (entries of a column in any order,
/// no repeated row within a column).
struct FclibLocalProblem {
  int rows = 0;                         ///< 2nc
  std::vector<std::int32_t> col_start;  ///< rows + 1, col_start[0] = 0, non-decreasing
  std::vector<std::int32_t> row_index;  ///< col_start[rows] entries in [0, rows)
  std::vector<double> values;           ///< col_start[rows] finite values
  std::vector<double> q;                ///< rows, finite
  std::vector<double> mu;               ///< rows / 2, finite, ≥ 0
  std::optional<FclibSolution> solution;  ///< /solution, when present
  std::vector<FclibSolution> guesses;     ///< /guesses/1 …, in order
};

/// Reads a local problem (and its /solution and /guesses if present). Throws IoError with one
/// line for a missing or non-HDF5 file, a global problem, spacedim ≠ 2, V/R present (mixed
/// problems), sizes that disagree with the datasets, indices out of range, repeated entries,
/// non-finite numbers or a negative μ.
FclibLocalProblem read_fclib_local(const std::string& path);

/// Writes `p` (W as compressed columns, nz = −1, nzmax = number of entries) with its solution
/// and guesses, atomically (dc::AtomicH5File). Throws InvalidArgument when `p` is inconsistent
/// (the checks of the reader), IoError when the file cannot be written.
void write_fclib_local(const std::string& path, const FclibLocalProblem& p);

}  // namespace dc
