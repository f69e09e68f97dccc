#pragma once
// 2D frictional-contact problems in the Siconos numerics `.dat` text format, as written by
// Siconos' frictionContact_printInFile and read by frictionContact_newFromFile
// (numerics/src/FrictionContact/FrictionContactProblem.c; docs/lcp.md, docs/formats.md):
//
//     d                      dimension of the contact law: 2 (3 is refused: 3D friction)
//     nc                     number of contacts (W is 2nc × 2nc)
//     storage                0 = dense, 1 = sparse block, 2 = sparse (CSparse print format)
//     rows                   (= 2nc)
//     cols                   (= 2nc)
//     W                      dense (0) and sparse block (1) as in LCP files (dat_file.hpp);
//                            sparse (2): the origin (1 triplet, 2 compressed column,
//                            3 compressed row), then CSparse's cs_print text:
//                              CSparse Version …            (one line, skipped)
//                              [csr: |triplet: ]M-by-N, nzmax: Z nnz: K[, 1-norm: x]
//                              compressed: per column (row) j "col j : locations a to b",
//                              then b − a + 1 lines "i : x"; triplet: K lines "i j : x"
//                            (values printed by Siconos with %g: 6 significant digits)
//     q(0) … q(2nc−1)
//     μ(0) … μ(nc−1)
//     anything else          a remark, kept as Fc2dDatFile::comment
//
// Validated like the LCP reader: every count checked against the bytes left before anything
// of that size is allocated, nothing read past the end, one-line dc::IoError
// "FILE: line L: what" for a missing or empty file, truncated data, non-numbers, NaN/Inf,
// nc ≤ 0 or 2nc > kMaxDatSize, a dimension other than 2, sizes that disagree, a negative μ,
// and the storage errors (a column header out of sequence, a row index out of range, an entry
// given twice, …).
#include <string>
#include <string_view>

#include "dc/lcp/dat_file.hpp"
#include "dc/lcp/fc2d_problem.hpp"

namespace dc {

/// How W was stored in a frictional-contact .dat file.
enum class Fc2dStorage { Dense = 0, SparseBlock = 1, Sparse = 2 };

/// A parsed 2D frictional-contact .dat file.
struct Fc2dDatFile {
  Fc2dProblem problem;
  Fc2dStorage storage = Fc2dStorage::Dense;
  std::string comment;  ///< text after μ, as DatFile::comment
};

/// Parses the text of a frictional-contact .dat file; `name` is used in messages. Throws IoError.
Fc2dDatFile parse_fc2d_dat(std::string_view text, const std::string& name);

/// Reads FILE.dat. Throws IoError.
Fc2dDatFile read_fc2d_dat(const std::string& path);

/// What a Siconos .dat file holds, judged from its first five numbers.
enum class DatKind { Lcp, Fc2d };

/// An LCP file starts "n storage n n" (storage 0 or 1), a frictional one "d nc storage d·nc d·nc"
/// (storage 0, 1 or 2; d = 2 or 3). When the header fits both (tiny problems) the one whose
/// whole parse succeeds wins (frictional first). Throws IoError when it fits neither.
DatKind detect_dat_kind(std::string_view text, const std::string& name);

/// Text of `p` in Siconos' frictional-contact format, W in storage 0 (dense) or 1 (sparse
/// block, 2 × 2 blocks per contact pair, only non-zero blocks), numbers with %.17g (exact
/// round trip). Throws InvalidArgument for another storage or an invalid problem.
std::string format_fc2d_dat(const Fc2dProblem& p, Fc2dStorage storage);

/// Writes format_fc2d_dat(p, storage) to `path`. Throws IoError / InvalidArgument.
void write_fc2d_dat(const std::string& path, const Fc2dProblem& p, Fc2dStorage storage);

}  // namespace dc
