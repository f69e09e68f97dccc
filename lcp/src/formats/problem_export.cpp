#include "dc/lcp/problem_export.hpp"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "dc/core/error.hpp"
#include "dc/io/output_path.hpp"
#include "dc/lcp/fc2d_problem.hpp"

namespace dc {

ProblemExporter::ProblemExporter(ProblemExportDef def) : def_(std::move(def)) {
  if (def_.every < 1) throw ConfigError("--every must be >= 1");
  if (def_.format != ProblemFormat::Fclib && def_.format != ProblemFormat::SiconosFc)
    throw ConfigError("exported problems are written as fclib or siconos-fc");
  std::error_code ec;
  std::filesystem::create_directories(def_.dir, ec);
  if (ec) throw IoError(def_.dir + ": cannot create the export folder: " + ec.message());
  check_output_directory(def_.dir);  // a read-only folder is refused now, not at the first export
}

std::string ProblemExporter::write(int step, const LcpProblem& problem, const Eigen::VectorXd& lambda,
                                   const Eigen::VectorXd& guess) {
  if (problem.rows() == 0) return "";
  const Fc2dFromLcp fc = fc2d_from_lcp(problem);
  char name[48];
  std::snprintf(name, sizeof name, "step_%06d.%s", step, def_.format == ProblemFormat::Fclib ? "hdf5" : "dat");
  const std::string path = (std::filesystem::path(def_.dir) / name).string();
  std::vector<Eigen::VectorXd> guesses;
  if (guess.size() == problem.rows()) guesses.push_back(fc2d_reactions(fc, guess));
  const Eigen::VectorXd solution = lambda.size() == problem.rows() ? fc2d_reactions(fc, lambda) : Eigen::VectorXd();
  write_fc2d_problem(path, fc.problem, def_.format, solution, guesses);
  ++written_;
  return path;
}

}  // namespace dc
