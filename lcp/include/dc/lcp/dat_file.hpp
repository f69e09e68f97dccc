#pragma once
// LCP problem files in the Siconos numerics `.dat` text format, storage 0 (dense) and 1 (sparse
// block), as Siconos' linearComplementarity_printInFile / NM_write_in_file / SBM_write_in_file
// write them; layout: docs/lcp.md "The `.dat` format", docs/design.md §7. The LCP is
// w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0, i.e. LcpProblem::standard(M, q) with M sparse (zeros not
// stored); text after q is a remark, kept as DatFile::comment. The reader is liberal with
// whitespace but strict up to the last entry of q: a missing file, truncated data, a non-numeric
// token, NaN/Inf, n ≤ 0 or n > 100000, disagreeing sizes, another storage type, block sizes not
// adding up to n, an index out of range, a repeated or out-of-order block, sizes the file is
// too short to hold, or a last entry of q without a line end after it (a file cut inside its
// last number: Siconos ends every vector with "\n") throw dc::IoError with one line naming
// the file, the line and the problem. The writers refuse what the reader refuses (n = 0,
// NaN/Inf: InvalidArgument).
// Every size is checked against the bytes left before allocating; reading never blocks.
#include <Eigen/Core>
#include <string>
#include <string_view>

#include "dc/lcp/lcp_problem.hpp"

namespace dc {

/// Largest n the reader accepts (a dense 100000² matrix is 80 GB already).
inline constexpr long long kMaxDatSize = 100000;

/// Most bytes read from a `.dat` that is not a regular file (a pipe, a character device
/// such as /dev/zero) [bytes]: more is refused. A regular file is read up to its size.
inline constexpr size_t kMaxDatStreamBytes = size_t{256} << 20;

/// Longest remark after q kept in DatFile::comment [bytes]; the rest is dropped.
inline constexpr size_t kMaxDatComment = 4096;

/// Siconos NumericsMatrix storage types the reader and writer understand.
enum class DatStorage { Dense = 0, SparseBlock = 1 };

/// A parsed .dat file: the problem, how M was stored, and the remark after q.
struct DatFile {
  LcpProblem problem;
  DatStorage storage = DatStorage::Dense;
  /// Text after the last entry of q, leading/trailing whitespace removed, at most
  /// kMaxDatComment bytes, invalid UTF-8 bytes replaced by '?'. Empty when there is none.
  std::string comment;
};

/// Reads FILE.dat (either storage). Throws IoError.
DatFile read_dat_file(const std::string& path);

/// Parses the text of a .dat file; `name` is used in error messages. Throws IoError.
DatFile parse_dat_file(std::string_view text, const std::string& name);

/// read_dat_file(path).problem: a standard LCP (lo = 0, hi = +∞, no friction).
LcpProblem read_lcp_dat(const std::string& path);

/// parse_dat_file(text, name).problem.
LcpProblem parse_lcp_dat(std::string_view text, const std::string& name);

/// Writes M, q in dense storage (numbers with %.17g, so a round trip is exact).
/// Throws IoError if the file cannot be written, InvalidArgument if sizes disagree.
void write_lcp_dat(const std::string& path, const Eigen::MatrixXd& M, const Eigen::VectorXd& q);

/// Text of the file write_lcp_dat writes.
std::string format_lcp_dat(const Eigen::MatrixXd& M, const Eigen::VectorXd& q);

/// Text of M, q in sparse-block storage (1) with square diagonal block structure: blocks of
/// `block_size` rows/columns (the last one smaller if block_size does not divide n); only
/// blocks with a non-zero entry are stored. Numbers with %.17g (exact round trip), integers
/// followed by a tab as Siconos writes them. Throws InvalidArgument if sizes disagree or
/// block_size < 1.
std::string format_lcp_dat_blocks(const SparseRowMatrix& M, const Eigen::VectorXd& q, int block_size);

/// Writes format_lcp_dat_blocks(M, q, block_size) to `path`. Throws IoError / InvalidArgument.
void write_lcp_dat_blocks(const std::string& path, const SparseRowMatrix& M, const Eigen::VectorXd& q,
                          int block_size);

}  // namespace dc
