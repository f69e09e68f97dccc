#pragma once
// LCP problem files in the Siconos numerics `.dat` text format (DESIGN §7), dense storage
// (type 0) only. The layout, as written by Siconos' linearComplementarity_printInFile /
// NM_write_in_file and read by linearComplementarity_newFromFile / NM_new_from_file:
//
//     n                      problem size
//     0                      storage type (0 = dense)
//     rows                   (= n)
//     cols                   (= n)
//     rows<TAB>cols          repeated size line of the dense block
//     M, column-major: M(0,j) M(1,j) … M(n−1,j), one column per line, j = 0 … n−1
//     q(0) … q(n−1)
//
// The LCP is w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0, i.e. LcpProblem::standard(M, q).
// The reader is liberal with whitespace (any mix of spaces, tabs, newlines; line breaks are
// not required where Siconos puts them) but strict about content: every failure — missing
// file, truncated data, a non-numeric token, NaN/Inf, n ≤ 0 or n > 100000, sizes that
// disagree, a storage type other than 0, more numbers than the sizes announce, or sizes
// the file is too short to hold — throws dc::IoError with one line naming the file and the
// problem. It never allocates more than the file can fill and never blocks.
#include <Eigen/Core>
#include <string>
#include <string_view>

#include "dc/engine/lcp_problem.hpp"

namespace dc {

/// Largest n the reader accepts (a dense 100000² matrix is 80 GB already).
inline constexpr long long kMaxDatSize = 100000;

/// Reads FILE.dat into a standard LCP (lo = 0, hi = +∞, no friction). Throws IoError.
LcpProblem read_lcp_dat(const std::string& path);

/// Parses the text of a .dat file; `name` is used in error messages. Throws IoError.
LcpProblem parse_lcp_dat(std::string_view text, const std::string& name);

/// Writes M, q in the format above (numbers with %.17g, so a round trip is exact).
/// Throws IoError if the file cannot be written, InvalidArgument if sizes disagree.
void write_lcp_dat(const std::string& path, const Eigen::MatrixXd& M, const Eigen::VectorXd& q);

/// Text of the file write_lcp_dat writes.
std::string format_lcp_dat(const Eigen::MatrixXd& M, const Eigen::VectorXd& q);

}  // namespace dc
