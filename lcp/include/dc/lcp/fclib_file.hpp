#pragma once
// FCLIB local frictional-contact problems (the HDF5 format of the FCLIB collection,
// https://frictionalcontactlibrary.github.io), spacedim 2 only: /fclib_local/{spacedim, W/{m,n,
// nz,nzmax,p,i,x}, vectors/{q,mu}}, optional /solution/{u,r} and /guesses; layout and index
// conventions in docs/formats.md "FCLIB local problems". libfclib reads what this writer writes
// and the other way round (tested). this reader does not call libfclib because it trusts the sizes
// stored in the file and calls exit(1) on an HDF5 error; here every size is checked against the
// datasets' shapes before reading, every index against the matrix, every value for finiteness,
// and errors are one-line dc::IoError messages "FILE: what".
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
