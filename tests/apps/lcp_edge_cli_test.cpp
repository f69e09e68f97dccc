// LCP edge cases end to end through `deepcontact lcp solve` (docs/robustness.md). The solvers'
// own edge-case behaviour is unit-tested in tests/lcp/solver_edge_test.cpp; this file
// checks what a user of the command sees for the same degenerate files: the exit status
// matches the JSON status (0 converged, 3 infeasible, 1 anything else), the status says what
// happened, nothing hangs, and no output ever contains a NaN or an Inf (JSON has neither;
// a non-finite number must be written as null).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cctype>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "apps/cli_helpers.hpp"
#include "dc/lcp/dat_file.hpp"

namespace dc {
namespace {

const std::vector<std::string> kSolvers = {"lemke", "newton", "pgs", "pgs-assembled", "psor", "jacobi"};

struct Outcome {
  int exit_code = -1;
  std::string status;  ///< the JSON "status" value without quotes ("" if missing)
  std::vector<double> z;
  std::string out, err;
};

std::string json_status(const std::string& json) {
  static const std::regex re("\"status\": \"([a-z_]+)\"");
  std::smatch m;
  return std::regex_search(json, m, re) ? std::string(m[1]) : std::string();
}

std::vector<double> json_z(const std::string& json) {
  static const std::regex re("\"z\": \\[([^\\]]*)\\]");
  std::smatch m;
  std::vector<double> z;
  if (!std::regex_search(json, m, re)) return z;
  const std::string body = m[1];
  std::size_t pos = 0;
  while (pos < body.size()) {
    std::size_t end = body.find(',', pos);
    if (end == std::string::npos) end = body.size();
    const std::string item = body.substr(pos, end - pos);
    z.push_back(item.find("null") != std::string::npos ? NAN : std::stod(item));
    pos = end + 1;
  }
  return z;
}

/// True when `text` contains "nan" or "inf" as a word (case-insensitive): what printf
/// writes for non-finite doubles.
bool has_non_finite_token(const std::string& text) {
  static const std::regex re("(^|[^a-zA-Z_])([nN][aA][nN]|[iI][nN][fF])([^a-zA-Z_]|$)");
  return std::regex_search(text, re);
}

class LcpEdgeCli : public ::testing::Test {
 protected:
  /// Writes M, q as a .dat file and runs `lcp solve` with `solver`.
  Outcome solve(const std::string& name, const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                const std::string& solver, const std::string& extra = "") {
    const std::string path = dir_.file(name + ".dat");
    write_lcp_dat(path, M, q);
    return run(path, solver, extra);
  }
  Outcome run(const std::string& path, const std::string& solver, const std::string& extra = "") {
    const test::CliResult r =
        test::run_cli("lcp solve \"" + path + "\" --solver " + solver + " " +
                      (extra.find("--sweeps") == std::string::npos ? "--sweeps 2000 " : "") + extra);
    Outcome o;
    o.exit_code = r.exit_code;
    o.status = json_status(r.out);
    o.z = json_z(r.out);
    o.out = r.out;
    o.err = r.err;
    return o;
  }
  /// The command's contract for any input it could read.
  static void expect_consistent(const Outcome& o, int n, const std::string& what) {
    EXPECT_FALSE(has_non_finite_token(o.out)) << what << ": " << o.out;
    EXPECT_FALSE(has_non_finite_token(o.err)) << what << ": " << o.err;
    ASSERT_FALSE(o.status.empty()) << what << ": no JSON status in " << o.out << o.err;
    const int want = o.status == "converged" ? 0 : o.status == "infeasible" ? 3 : 1;
    EXPECT_EQ(o.exit_code, want) << what << ": status " << o.status;
    ASSERT_EQ(static_cast<int>(o.z.size()), n) << what << ": " << o.out;
    for (double v : o.z) EXPECT_TRUE(std::isfinite(v)) << what << ": z has a null (non-finite) entry: " << o.out;
  }
  test::TempDir dir_;
};

Eigen::MatrixXd mat(std::initializer_list<std::initializer_list<double>> rows) {
  const int n = static_cast<int>(rows.size());
  Eigen::MatrixXd A(n, n);
  int i = 0;
  for (const auto& r : rows) {
    int j = 0;
    for (double v : r) A(i, j++) = v;
    ++i;
  }
  return A;
}

Eigen::VectorXd vec(std::initializer_list<double> v) {
  return Eigen::Map<const Eigen::VectorXd>(v.begin(), static_cast<Eigen::Index>(v.size()));
}

TEST_F(LcpEdgeCli, OneRowIsSolvedByEverySolver) {
  for (const auto& s : kSolvers) {
    const Outcome o = solve("n1", mat({{4}}), vec({-2}), s, "--tol 1e-12");
    expect_consistent(o, 1, s);
    EXPECT_EQ(o.status, "converged") << s << ": " << o.out;
    ASSERT_EQ(o.z.size(), 1u);
    EXPECT_NEAR(o.z[0], 0.5, 1e-9) << s;
  }
}

TEST_F(LcpEdgeCli, NonNegativeQGivesZero) {
  for (const auto& s : kSolvers) {
    const Outcome o = solve("qpos", mat({{1, 2}, {3, -4}}), vec({0.5, 0.0}), s, "--tol 1e-12");
    expect_consistent(o, 2, s);
    EXPECT_EQ(o.status, "converged") << s;
    for (double v : o.z) EXPECT_EQ(v, 0.0) << s;
  }
}

TEST_F(LcpEdgeCli, ZeroRowAndZeroDiagonalWithASolution) {
  // Row 1 all zero with q_1 ≥ 0; and a zero diagonal in a coupled row (solution (0, 0.5)).
  for (const auto& s : kSolvers) {
    const Outcome row = solve("zero_row", mat({{2, 0, 1}, {0, 0, 0}, {1, 0, 3}}), vec({-1, 0.5, -1}), s,
                              "--tol 1e-12 --sweeps 5000");
    expect_consistent(row, 3, s + " zero row");
    EXPECT_EQ(row.status, "converged") << s << ": " << row.out;
    const Outcome diag = solve("zero_diag", mat({{0, 1}, {1, 2}}), vec({1, -1}), s, "--tol 1e-12 --sweeps 5000");
    expect_consistent(diag, 2, s + " zero diagonal");
    EXPECT_EQ(diag.status, "converged") << s << ": " << diag.out;
    if (diag.z.size() == 2) {
      EXPECT_NEAR(diag.z[1], 0.5, 1e-8) << s;
    }
  }
}

TEST_F(LcpEdgeCli, ZeroDiagonalWithoutASolutionIsReportedNotHidden) {
  // w_0 = −1 whatever z is: no solution. Lemke proves it (exit 3); the sweep methods cannot
  // take a diagonal step on row 0 and say so (status failed, exit 1); none claims success.
  for (const auto& s : kSolvers) {
    const Outcome o = solve("stuck", mat({{0, 0}, {0, 1}}), vec({-1, -1}), s);
    expect_consistent(o, 2, s);
    EXPECT_NE(o.status, "converged") << s << ": " << o.out;
  }
  EXPECT_EQ(solve("stuck", mat({{0, 0}, {0, 1}}), vec({-1, -1}), "lemke").exit_code, 3);
  const Outcome pgs = solve("stuck", mat({{0, 0}, {0, 1}}), vec({-1, -1}), "pgs-assembled");
  EXPECT_EQ(pgs.status, "failed") << pgs.out;
  EXPECT_NE(pgs.out.find("diagonal"), std::string::npos) << "the message names the cause: " << pgs.out;
}

TEST_F(LcpEdgeCli, ZeroMatrix) {
  // M = 0, q ≥ 0: z = 0 solves it.
  for (const auto& s : kSolvers) {
    const Outcome o = solve("m0_ok", Eigen::MatrixXd::Zero(3, 3), vec({0, 1, 2}), s);
    expect_consistent(o, 3, s);
    EXPECT_EQ(o.status, "converged") << s << ": " << o.out;
  }
  // M = 0, q < 0: infeasible; no solver may converge or pretend to have run out of sweeps.
  for (const auto& s : kSolvers) {
    const Outcome o = solve("m0_bad", Eigen::MatrixXd::Zero(2, 2), vec({-1, -2}), s);
    expect_consistent(o, 2, s);
    EXPECT_NE(o.status, "converged") << s;
    EXPECT_NE(o.status, "sweep_limit") << s;
  }
  EXPECT_EQ(solve("m0_bad", Eigen::MatrixXd::Zero(2, 2), vec({-1, -2}), "lemke").status, "infeasible");
}

TEST_F(LcpEdgeCli, InfeasibleProblems) {
  // Skew-symmetric (copositive-plus) and negative definite, both with no solution.
  const Eigen::MatrixXd skew = mat({{0, -1}, {1, 0}}), negdef = mat({{-1, 0}, {0, -1}});
  for (const Eigen::MatrixXd* M : {&skew, &negdef}) {
    const Outcome lemke = solve("inf", *M, vec({-1, -1}), "lemke");
    expect_consistent(lemke, 2, "lemke");
    EXPECT_EQ(lemke.status, "infeasible");
    EXPECT_EQ(lemke.exit_code, 3);
    for (const auto& s : kSolvers) {
      const Outcome o = solve("inf", *M, vec({-1, -1}), s);
      expect_consistent(o, 2, s);
      EXPECT_NE(o.status, "converged") << s << ": " << o.out;
    }
  }
}

TEST_F(LcpEdgeCli, ValuesNearOverflow) {
  // Well-scaled in relative terms: every solver finds z = (1, 0.1).
  for (const auto& s : kSolvers) {
    const Outcome o = solve("big", mat({{1e300, 0}, {0, 1e300}}), vec({-1e300, -1e299}), s, "--tol 1e-12");
    expect_consistent(o, 2, s);
    EXPECT_EQ(o.status, "converged") << s << ": " << o.out;
    if (o.z.size() == 2) {
      EXPECT_NEAR(o.z[0], 1.0, 1e-9) << s;
    }
  }
  // Products overflow inside the iterations: any status is acceptable, NaN/Inf output is not.
  for (const auto& s : kSolvers) {
    const Outcome o = solve("wild", mat({{1e-300, 1e300}, {-1e300, 1e-300}}), vec({-1e300, 1e300}), s);
    expect_consistent(o, 2, s);
  }
  // Tiny values (near underflow) scale the other way.
  for (const auto& s : kSolvers) {
    const Outcome o = solve("tiny", mat({{1e-300, 0}, {0, 2e-300}}), vec({-1e-300, -1e-300}), s, "--tol 0");
    EXPECT_FALSE(has_non_finite_token(o.out)) << s << ": " << o.out;
    ASSERT_FALSE(o.status.empty()) << s << ": " << o.err;
  }
}

TEST_F(LcpEdgeCli, NonFiniteAndEmptyFilesAreOneLineErrors) {
  // The reader refuses NaN/Inf and n = 0 before any solver runs: exit 1, one line on stderr,
  // nothing on stdout.
  const std::vector<std::pair<std::string, std::string>> files = {
      {"nan", "1\n0\n1\n1\n1\t1\nnan\n-1\n"},
      {"inf", "1\n0\n1\n1\n1\t1\n1\ninf\n"},
      {"overflowing_literal", "1\n0\n1\n1\n1\t1\n1e400\n-1\n"},
      {"empty_problem", "0\n0\n0\n0\n0\t0\n"},
  };
  for (const auto& [name, text] : files) {
    const std::string path = dir_.file(name + ".dat");
    std::ofstream(path) << text;
    const test::CliResult r = test::run_cli("lcp solve \"" + path + "\"");
    EXPECT_EQ(r.exit_code, 1) << name << ": " << r.out << r.err;
    EXPECT_TRUE(r.out.empty()) << name << ": " << r.out;
    ASSERT_FALSE(r.err.empty()) << name;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << name << ": one line: " << r.err;
    EXPECT_NE(r.err.find(name + ".dat"), std::string::npos) << name << ": names the file: " << r.err;
  }
}

TEST_F(LcpEdgeCli, NonConvergingIterationsStopAtTheSweepLimit) {
  // Undamped projected Jacobi on a strongly coupled matrix does not converge: with a huge
  // sweep budget the command still returns promptly (divergence detection or the limit).
  Eigen::MatrixXd M = mat({{1, 0.9, 0.9}, {0.9, 1, 0.9}, {0.9, 0.9, 1}});
  const Outcome o = solve("coupled", M, vec({-1, -1, -1}), "jacobi", "--tol 1e-14 --sweeps 1000000");
  expect_consistent(o, 3, "jacobi");
  EXPECT_NE(o.status, "converged") << o.out;
}

}  // namespace
}  // namespace dc
