#pragma once
// Writes the frictional-contact problem of simulation steps to files, so that others can run
// their solvers — and their warm starts — on the engine's scenes (`deepcontact simulate
// --export-problems DIR [--every K] [--format fclib|siconos-fc]`, docs/lcp.md).
//
// Each exported step k (k = every, 2·every, …; steps without contacts are skipped) becomes
// DIR/step_KKKKKK.hdf5 (FCLIB: W, q, μ, the solver's λ as /solution, the warm starter's
// guess as /guesses/1) or DIR/step_KKKKKK.dat (Siconos frictional-contact .dat, sparse-block
// storage; no solution or guess: the format has no place for them). Rows are reordered per
// contact (normal, tangent) by fc2d_from_lcp; frictionless contacts get a decoupled tangent
// row (fc2d_problem.hpp).
#include <Eigen/Core>
#include <string>

#include "dc/lcp/problem_file.hpp"
#include "dc/lcp/lcp_problem.hpp"

namespace dc {

struct ProblemExportDef {
  std::string dir;                               ///< output folder (created if missing)
  int every = 1;                                 ///< export steps every, 2·every, … (≥ 1)
  ProblemFormat format = ProblemFormat::Fclib;   ///< fclib or siconos-fc
};

class ProblemExporter {
 public:
  /// Creates `def.dir`. Throws ConfigError for every < 1 or a format other than fclib and
  /// siconos-fc, IoError when the folder cannot be created or no file can be created in it (checked
  /// here, before the run that exports).
  explicit ProblemExporter(ProblemExportDef def);

  /// True when step `step` (1-based) is to be exported.
  [[nodiscard]] bool due(int step) const { return step % def_.every == 0; }

  /// Writes the step's problem with the solver's λ and the warm start λ⁰ (either may be empty:
  /// then not written). Returns the file's path, or "" when the problem has no rows.
  std::string write(int step, const LcpProblem& problem, const Eigen::VectorXd& lambda,
                    const Eigen::VectorXd& guess);

  /// Files written so far.
  [[nodiscard]] int written() const { return written_; }

 private:
  ProblemExportDef def_;
  int written_ = 0;
};

}  // namespace dc
