// `deepcontact lcp solve`: JSON on stdout, exit codes, one-line errors.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sys/wait.h>
#include <unistd.h>

#include "dc/lcp/dat_file.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"

namespace dc {
namespace {

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("dc_lcp_cli_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

CliRun run_cli(const std::string& args) {
  const std::string err_path = temp_path("stderr.txt");
  const std::string cmd = std::string("\"") + DC_CLI + "\" " + args + " 2>\"" + err_path + "\"";
  CliRun r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  size_t got;
  while ((got = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), got);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream e(err_path);
  r.err.assign(std::istreambuf_iterator<char>(e), std::istreambuf_iterator<char>());
  std::filesystem::remove(err_path);
  return r;
}

/// The numbers of the JSON array `key` (a tiny parser for our own flat output).
std::vector<double> json_array(const std::string& json, const std::string& key) {
  const std::regex re("\"" + key + "\": \\[([^\\]]*)\\]");
  std::smatch m;
  std::vector<double> v;
  if (!std::regex_search(json, m, re)) return v;
  std::string body = m[1];
  size_t pos = 0;
  while (pos < body.size()) {
    size_t end = body.find(',', pos);
    if (end == std::string::npos) end = body.size();
    v.push_back(std::stod(body.substr(pos, end - pos)));
    pos = end + 1;
  }
  return v;
}

std::string json_field(const std::string& json, const std::string& key) {
  const std::regex re("\"" + key + "\": (\"[^\"]*\"|[^,}]*)");
  std::smatch m;
  return std::regex_search(json, m, re) ? std::string(m[1]) : std::string();
}

TEST(LcpCli, SolvesAFileAndPrintsJson) {
  Eigen::MatrixXd M(3, 3);
  M << 2, 1, 0, 1, 3, 1, 0, 1, 4;
  M(0, 2) = 0.5;  // not symmetric: column-major order matters
  const Eigen::Vector3d q(-1, -2, 1);
  const std::string path = temp_path("p.dat");
  write_lcp_dat(path, M, q);
  for (const char* solver : {"lemke", "newton", "pgs"}) {
    const CliRun r = run_cli("lcp solve \"" + path + "\" --solver " + solver + " --tol 1e-14 --sweeps 100000");
    EXPECT_EQ(r.exit_code, 0) << solver << ": " << r.out << r.err;
    EXPECT_EQ(json_field(r.out, "status"), "\"converged\"") << r.out;
    const auto z = json_array(r.out, "z"), w = json_array(r.out, "w");
    ASSERT_EQ(z.size(), 3u) << r.out;
    ASSERT_EQ(w.size(), 3u);
    const Eigen::Vector3d zv(z[0], z[1], z[2]);
    const Eigen::Vector3d wv = M * zv + q;
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(w[static_cast<size_t>(i)], wv[i], 1e-12);  // w printed is M z + q
      EXPECT_GE(z[static_cast<size_t>(i)], 0.0);
      EXPECT_GE(w[static_cast<size_t>(i)], -1e-9);
      EXPECT_LE(std::min(z[static_cast<size_t>(i)], w[static_cast<size_t>(i)]), 1e-9);
    }
    EXPECT_FALSE(json_field(r.out, "sweeps").empty());
    EXPECT_LE(std::stod(json_field(r.out, "residual")), 1e-9);
  }
  std::filesystem::remove(path);
}

TEST(LcpCli, ShippedExampleSolves) {
  // The printed z must solve the file's LCP (w = M z + q, z ≥ 0, w ≥ 0, z ∘ w = 0) and agree
  // with an independent pivoting solve of the same file.
  const std::string path = std::string(DC_SOURCE_DIR) + "/tests/data/lcp/contact_12.dat";
  const CliRun r = run_cli("lcp solve \"" + path + "\"");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(json_field(r.out, "status"), "\"converged\"") << r.out;
  const LcpProblem p = read_lcp_dat(path);
  const auto z = json_array(r.out, "z"), w = json_array(r.out, "w");
  ASSERT_EQ(z.size(), 12u) << r.out;
  ASSERT_EQ(w.size(), 12u) << r.out;
  const Eigen::VectorXd zv = Eigen::Map<const Eigen::VectorXd>(z.data(), 12);
  const Eigen::VectorXd wv = p.A * zv + p.b;
  const double scale = p.b.cwiseAbs().maxCoeff();
  SolverOptions o;
  o.exact_tolerance = 1e-12;
  const SolveResult known = make_solver("lemke")->solve(p, Eigen::VectorXd(), o);
  ASSERT_EQ(known.status, SolveStatus::Converged) << known.message;
  const Eigen::VectorXd w_known = lcp_velocity(p, known.lambda);
  int active = 0;
  for (int i = 0; i < 12; ++i) {
    const auto k = static_cast<size_t>(i);
    EXPECT_NEAR(w[k], wv[i], 1e-9 * scale) << "row " << i;  // w printed is M z + q
    EXPECT_GE(z[k], 0.0) << "row " << i;
    EXPECT_GE(w[k], -1e-6 * scale) << "row " << i;
    EXPECT_LE(std::min(z[k], w[k] / scale), 1e-6 * std::max(1.0, zv.cwiseAbs().maxCoeff())) << "row " << i;
    EXPECT_NEAR(z[k], known.lambda[i], 1e-5 * std::max(1.0, known.lambda.cwiseAbs().maxCoeff())) << "row " << i;
    EXPECT_NEAR(w[k], w_known[i], 1e-6 * scale) << "row " << i;
    active += z[k] > 0 ? 1 : 0;
  }
  EXPECT_GT(active, 0);  // a contact problem with load: not the trivial z = 0
}

TEST(LcpCli, InfeasibleExitsWith3AndSweepLimitWith1) {
  const CliRun inf = run_cli(std::string("lcp solve \"") + DC_SOURCE_DIR + "/tests/data/lcp/infeasible.dat\"");
  EXPECT_EQ(inf.exit_code, 3) << inf.out << inf.err;
  EXPECT_EQ(json_field(inf.out, "status"), "\"infeasible\"");
  const CliRun lim = run_cli(std::string("lcp solve \"") + DC_SOURCE_DIR +
                             "/tests/data/lcp/small_spd.dat\" --solver pgs-assembled --sweeps 2 --tol 0");
  EXPECT_EQ(lim.exit_code, 1) << lim.out << lim.err;
  EXPECT_EQ(json_field(lim.out, "status"), "\"sweep_limit\"");
  EXPECT_EQ(json_field(lim.out, "sweeps"), "2");
}

TEST(LcpCli, BadFileGivesOneLineErrorAndNonZeroExit) {
  const std::string path = temp_path("bad.dat");
  std::ofstream(path) << "2\n0\n2\n2\n2\t2\n1 2\n3 oops\n1 1\n";
  const CliRun r = run_cli("lcp solve \"" + path + "\"");
  std::filesystem::remove(path);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(r.out.empty()) << r.out;
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
  EXPECT_NE(r.err.find("bad.dat"), std::string::npos) << r.err;
  const CliRun missing = run_cli("lcp solve /nonexistent/none.dat");
  EXPECT_NE(missing.exit_code, 0);
  const CliRun unknown = run_cli(std::string("lcp solve \"") + DC_SOURCE_DIR +
                                 "/tests/data/lcp/small_spd.dat\" --solver magic");
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_NE(unknown.err.find("lemke"), std::string::npos) << unknown.err;
}

TEST(LcpCli, WithoutASolverEveryLcpFileTakesLemkesRoute) {
  // The default route of an LCP is lemke: the same answer, status and exit code as naming it;
  // the JSON says which route ran. Every file of tests/data/lcp, listed from the folder.
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::string(DC_SOURCE_DIR) + "/tests/data/lcp")) {
    if (e.path().extension() != ".dat") continue;
    SCOPED_TRACE(e.path().string());
    ++files;
    const CliRun d = run_cli("lcp solve \"" + e.path().string() + "\"");
    const CliRun l = run_cli("lcp solve \"" + e.path().string() + "\" --solver lemke");
    EXPECT_EQ(d.exit_code, l.exit_code) << d.err;
    EXPECT_NE(d.exit_code, 2) << d.err;
    EXPECT_EQ(json_field(d.out, "route"), "\"lemke\"");
    EXPECT_EQ(json_field(d.out, "solver"), "\"lemke\"");
    EXPECT_EQ(json_field(d.out, "status"), json_field(l.out, "status"));
    EXPECT_EQ(json_array(d.out, "z"), json_array(l.out, "z"));
    EXPECT_EQ(d.out.find("\"r\": ["), std::string::npos);
  }
  EXPECT_GE(files, 9);
}

TEST(LcpCli, MessagesPrintSmallNumbersReadably) {
  // A stalled Newton reports its residual and target in %g, never as 0.000000.
  const CliRun r = run_cli(std::string("lcp solve \"") + DC_SOURCE_DIR +
                           "/tests/data/fc2d/FrictionContactProblem00727.dat\" --solver newton-sparse --sweeps 2 --tol 1e-12");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  const std::string msg = json_field(r.out, "message");
  EXPECT_NE(msg.find("above target 1e-12 N"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("0.000000"), std::string::npos) << msg;
}

TEST(LcpCli, AnIntegerOptionTakesAnExactIntegerInAnyNotation) {
  const std::string file = std::string("\"") + DC_SOURCE_DIR + "/tests/data/lcp/small_spd.dat\" --solver pgs-assembled --tol 0";
  const CliRun a = run_cli("lcp solve " + file + " --sweeps 1e1");
  EXPECT_EQ(a.exit_code, 1) << a.err;
  EXPECT_EQ(json_field(a.out, "sweeps"), "10");
  const CliRun b = run_cli("lcp solve " + file + " --sweeps 2.5");
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("--sweeps: 2.5 is not an integer"), std::string::npos) << b.err;
}

TEST(LcpCli, HelpDescribesTheCommand) {
  const CliRun r = run_cli("lcp solve --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--solver"), std::string::npos);
  EXPECT_NE(r.out.find("--sweeps"), std::string::npos);
  EXPECT_NE(r.out.find("--tol"), std::string::npos);
  EXPECT_NE(r.out.find(".dat"), std::string::npos);
}

}  // namespace
}  // namespace dc
