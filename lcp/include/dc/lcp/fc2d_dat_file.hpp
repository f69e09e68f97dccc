#pragma once
// 2D frictional-contact problems in the Siconos numerics `.dat` text format, as Siconos'
// frictionContact_printInFile writes and frictionContact_newFromFile reads them: d = 2 (3D
// friction refused), nc contacts, W (2nc × 2nc) in storage 0 (dense), 1 (sparse block, as
// dat_file.hpp) or 2 (CSparse's cs_print text), then q (2nc) and μ (nc), then optionally
// Siconos' `isComplete` flag (one integer, 0 or 1, that frictionContact_printInFile writes after
// μ and frictionContact_newFromFile reads back; Fc2dDatFile::is_complete); any other text after
// μ (or after the flag) is Fc2dDatFile::comment. Layout: docs/formats.md (frictionContact files), docs/lcp.md.
// Validated like the LCP reader: every count checked against the bytes left before anything
// of that size is allocated, nothing read past the end, one-line dc::IoError
// "FILE: line L: what" for a missing or empty file, truncated data, non-numbers, NaN/Inf,
// nc ≤ 0 or 2nc > kMaxDatSize, a dimension other than 2, sizes that disagree, a negative μ,
// the storage errors (a column header out of sequence, a row index out of range, an entry
// given twice — also in a CSparse triplet list —, …), and a last μ without a line end after it
// (possibly cut inside its last number). Read like the LCP reader: a regular file up to its
// size, a pipe or device up to kMaxDatStreamBytes.
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
  /// Siconos' isComplete flag after μ (0 or 1; −1 when the file has none). It says nothing
  /// about W, q or μ and is not written back.
  int is_complete = -1;
  std::string comment;  ///< text after μ and the flag, as DatFile::comment
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
