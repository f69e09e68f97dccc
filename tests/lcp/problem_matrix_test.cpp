// The data × solver matrix: every problem file under tests/data (Siconos LCP and 2D
// frictional-contact .dat) read through read_problem_file and handed to every solver of
// solver_names() and to the proximal route. Modelled on Siconos numerics' data_collection tests:
// one case per (file, solver), each checking the contracts every solver shares (lcp_solver.hpp):
//   * the result has one finite entry per row; a sweep solver stops at max_sweeps;
//   * the reported residual is the natural-map residual of the returned λ;
//   * Infeasible only for the files that have no solution, and never Converged on those;
//   * lemke, which takes standard LCPs only, refuses a frictional problem as InvalidInput;
//   * an exact method that says Converged is within its tolerance on the natural map.
// The two largest Siconos files (2020 and 7002 contacts) are left to `deepcontact lcp solve`
// and the bench: a solve there takes seconds, and this matrix runs in every `make test`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/problem_file.hpp"
#include "dc/lcp/proximal_point.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

/// Files of the matrix: every .dat under tests/data/lcp and tests/data/fc2d below the size cut.
std::vector<std::string> problem_files() {
  std::vector<std::string> files;
  for (const char* sub : {"lcp", "fc2d"}) {
    for (const auto& e : fs::directory_iterator(fs::path(DC_SOURCE_DIR) / "tests" / "data" / sub)) {
      if (e.path().extension() != ".dat") continue;
      if (fs::file_size(e.path()) > 1'000'000) continue;  // 2020 and 7002 contacts: see above
      const std::string stem = e.path().stem().string();
      if (stem.find("02020") != std::string::npos) continue;
      files.push_back(std::string(sub) + "/" + e.path().filename().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

/// Every solver name, plus "proximal" for solve_proximal_point (lcp solve --proximal).
std::vector<std::string> matrix_solvers() {
  std::vector<std::string> names = solver_names();
  names.push_back("proximal");
  return names;
}

bool is_infeasible_file(const std::string& file) { return file.find("infeasible") != std::string::npos; }

struct Case {
  std::string file;
  std::string solver;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.file << " with " << c.solver; }

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  for (const auto& f : problem_files())
    for (const auto& s : matrix_solvers()) cases.push_back({f, s});
  return cases;
}

std::string case_name(const testing::TestParamInfo<Case>& info) {
  std::string n = info.param.file + "_" + info.param.solver;
  for (char& c : n)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return n;
}

class ProblemMatrix : public testing::TestWithParam<Case> {};

TEST_P(ProblemMatrix, SharedSolverContracts) {
  const Case& c = GetParam();
  const ProblemFile file = read_problem_file((fs::path(DC_SOURCE_DIR) / "tests" / "data" / c.file).string());
  const LcpProblem& p = file.lcp;
  ASSERT_GT(p.rows(), 0);
  SolverOptions o;
  o.max_sweeps = 200;
  o.tolerance = 1e-10;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.rows());
  SolveResult r;
  if (c.solver == "proximal") {
    r = solve_proximal_point(p, zero, o);
  } else {
    const auto solver = make_solver(c.solver);
    r = solver->solve(p, zero, o);
  }
  SCOPED_TRACE(c.file + " with " + c.solver + ": " + to_string(r.status) + " after " + std::to_string(r.sweeps) +
               " (" + r.message + ")");

  if (c.solver == "lemke" && file.kind == ProblemKind::Fc2d) {
    EXPECT_EQ(r.status, SolveStatus::InvalidInput);
    return;
  }
  if (r.status == SolveStatus::InvalidInput) {
    ADD_FAILURE() << "a valid problem file was refused";
    return;
  }
  ASSERT_EQ(r.lambda.size(), p.rows());
  EXPECT_TRUE(r.lambda.allFinite());
  EXPECT_GE(r.sweeps, 0);
  // The sweep solvers stop at max_sweeps; the exact ones count their pivots or iterations plus
  // the sweeps of their own PGS polish, which has a budget of its own.
  const bool exact = c.solver == "lemke" || c.solver == "newton" || c.solver == "newton-sparse" || c.solver == "proximal" ||
                     c.solver == "prox-newton";
  if (!exact) {
    EXPECT_LE(r.sweeps, o.max_sweeps);
  }
  // The reported residual is the natural map at the returned λ (up to the round-off of a
  // matrix-free product against the assembled one).
  const double residual = natural_residual(p, r.lambda);
  EXPECT_NEAR(r.residual, residual, 1e-9 * std::max(1.0, residual));

  if (is_infeasible_file(c.file)) {
    EXPECT_NE(r.status, SolveStatus::Converged) << "a problem without a solution";
  } else {
    EXPECT_NE(r.status, SolveStatus::Infeasible) << "a problem that has a solution";
  }
  if (exact && r.status == SolveStatus::Converged) {
    const double scale = std::max(1.0, p.b.lpNorm<Eigen::Infinity>());
    EXPECT_LE(residual, 1e-6 * scale);
  }
}

INSTANTIATE_TEST_SUITE_P(DataCollection, ProblemMatrix, testing::ValuesIn(all_cases()), case_name);

// The matrix is not empty and covers both kinds of file: a renamed data folder must not turn
// it into a suite of zero cases.
TEST(ProblemMatrixFiles, BothKindsPresent) {
  const auto files = problem_files();
  EXPECT_GE(std::count_if(files.begin(), files.end(), [](const auto& f) { return f.starts_with("lcp/"); }), 5);
  EXPECT_GE(std::count_if(files.begin(), files.end(), [](const auto& f) { return f.starts_with("fc2d/"); }), 8);
}

}  // namespace
}  // namespace dc
