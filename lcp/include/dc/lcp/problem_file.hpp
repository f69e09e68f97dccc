#pragma once
// Problem files of every kind the project reads and writes, behind one call (docs/lcp.md):
//   * Siconos LCP `.dat` (dc/lcp/dat_file.hpp): a standard LCP;
//   * Siconos frictional-contact `.dat`, dimension 2 (dc/lcp/fc2d_dat_file.hpp);
//   * FCLIB local problems, spacedim 2 (HDF5, dc/lcp/fclib_file.hpp), with /solution, /guesses.
// A frictional problem is handed to the solvers as its box-friction LCP (fc2d_to_lcp).
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "dc/lcp/fc2d_problem.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/fclib_file.hpp"

namespace dc {

/// What a problem file holds: a standard LCP or a 2D frictional-contact problem.
enum class ProblemKind { Lcp, Fc2d };
/// "lcp", "fc2d".
const char* to_string(ProblemKind k);
/// "lcp" / "fc2d" → the kind; ConfigError otherwise.
ProblemKind parse_problem_kind(const std::string& name);

/// The file formats: Siconos LCP .dat, Siconos frictional-contact .dat, FCLIB (HDF5).
enum class ProblemFormat { SiconosLcp, SiconosFc, Fclib };
/// "siconos-lcp", "siconos-fc", "fclib".
const char* to_string(ProblemFormat f);
/// The inverse of to_string; ConfigError otherwise.
ProblemFormat parse_problem_format(const std::string& name);

/// A problem read from a file.
struct ProblemFile {
  ProblemKind kind = ProblemKind::Lcp;
  ProblemFormat format = ProblemFormat::SiconosLcp;
  LcpProblem lcp;    ///< what a solver takes (for fc2d: fc2d_to_lcp(fc2d))
  Fc2dProblem fc2d;  ///< kind == Fc2d only
  std::string comment;  ///< the remark after the last vector of a .dat file ("" if none)
  Eigen::VectorXd solution;              ///< FCLIB /solution r; empty when there is none
  std::vector<Eigen::VectorXd> guesses;  ///< FCLIB /guesses r, in order
};

/// Reads `path`: an HDF5 file (by its signature) as FCLIB, any other as Siconos .dat whose
/// kind is detected from its header (detect_dat_kind) unless `force` says it. Throws IoError
/// (one line) for unreadable or malformed files, ConfigError when `force` contradicts an
/// FCLIB file (which always holds a frictional problem).
ProblemFile read_problem_file(const std::string& path, std::optional<ProblemKind> force = {});

/// Writes a frictional problem as FCLIB (with r = `solution` as /solution and each guess as a
/// /guesses entry, u = W r + q computed for each) or as a Siconos frictional-contact .dat file
/// (sparse-block storage; a .dat file has no place for solutions or guesses, they are not
/// written). Throws InvalidArgument for vectors of the wrong size, IoError when writing fails.
void write_fc2d_problem(const std::string& path, const Fc2dProblem& p, ProblemFormat format,
                        const Eigen::VectorXd& solution = Eigen::VectorXd(),
                        const std::vector<Eigen::VectorXd>& guesses = {});

/// The format a file name asks for: FCLIB for `.hdf5` or `.h5`; otherwise the Siconos .dat of
/// the problem's kind (LCP or frictional contact).
ProblemFormat problem_format_for_path(const std::string& path, ProblemKind kind);

/// How write_problem_file lays out a Siconos LCP .dat (the other formats have one layout).
struct ProblemWriteDef {
  std::optional<ProblemFormat> format;  ///< empty = problem_format_for_path
  int storage = 0;                      ///< LCP .dat: 0 dense, 1 sparse block
  int block = 0;                        ///< LCP .dat with storage 1: block size (0 = one block)
};

/// Writes `file` (as read_problem_file returns it) in the format `def` names or the path asks
/// for: an LCP as Siconos LCP .dat (dense or sparse block), a frictional problem as FCLIB (with
/// its solution and guesses) or Siconos frictional-contact .dat (write_fc2d_problem). The
/// remark after the last vector of a .dat file is not written. Throws ConfigError for a format
/// that cannot hold the problem's kind or a bad storage/block, IoError when writing fails.
void write_problem_file(const std::string& path, const ProblemFile& file, const ProblemWriteDef& def = {});

/// FCLIB local problem ↔ the engine's frictional problem (W, q, μ copied bit for bit).
Fc2dProblem fc2d_from_fclib(const FclibLocalProblem& f);
FclibLocalProblem fclib_from_fc2d(const Fc2dProblem& p);

}  // namespace dc
