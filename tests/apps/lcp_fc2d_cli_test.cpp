// `deepcontact lcp solve` / `lcp convert` / `simulate --export-problems` on 2D frictional-contact
// problems (docs/lcp.md): Siconos' own 2D test files solved (checked here from the file),
// FCLIB in and out with bit-equal round trips, and hostile files refused with one line.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "apps/cli_helpers.hpp"
#include "dc/lcp/problem_file.hpp"
#include "dc/lcp/fc2d_dat_file.hpp"

namespace dc {
namespace {

const std::string kData = std::string(DC_SOURCE_DIR) + "/tests/data/fc2d/";

/// The numbers of the JSON array that follows `"key": ` in `json`.
Eigen::VectorXd array_of(const std::string& json, const std::string& key) {
  const size_t k = json.find("\"" + key + "\": [");
  if (k == std::string::npos) return {};
  std::string body = json.substr(json.find('[', k) + 1, json.find(']', k) - json.find('[', k) - 1);
  std::replace(body.begin(), body.end(), ',', ' ');
  std::istringstream in(body);
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return Eigen::Map<Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

std::string member(const std::string& json, const std::string& key) {
  const size_t k = json.find("\"" + key + "\": ");
  if (k == std::string::npos) return "";
  const size_t b = k + key.size() + 4;
  return json.substr(b, json.find_first_of(",}", b) - b);
}

/// Solves one file of tests/data/fc2d with `solver_args` and checks the answer from the file:
/// converged, u = W r + q, and the natural residual of r ≤ 1e-8·max(1, ‖q‖∞). Returns the JSON.
std::string expect_solved(const std::string& name, const std::string& solver_args) {
  SCOPED_TRACE(name);
  const test::CliResult r = test::run_cli("lcp solve \"" + kData + name + "\" " + solver_args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");  // no note: Siconos' isComplete flag after mu is read as what it is
  EXPECT_EQ(member(r.out, "problem"), "\"fc2d\"");
  EXPECT_EQ(r.out.find("\"z\""), std::string::npos);  // FCLIB's names for a frictional problem
  EXPECT_EQ(member(r.out, "status"), "\"converged\"");
  EXPECT_GE(std::stod(member(r.out, "solve_seconds")), 0.0);
  const Fc2dProblem p = read_fc2d_dat(kData + name).problem;
  const Eigen::VectorXd z = array_of(r.out, "r"), w = array_of(r.out, "u"), mu = array_of(r.out, "mu");
  if (z.size() != p.q.size()) {
    ADD_FAILURE() << r.out.substr(0, 300);
    return r.out;
  }
  EXPECT_EQ(mu, p.mu);
  EXPECT_LE((w - (p.W * z + p.q)).lpNorm<Eigen::Infinity>(), 1e-12 * std::max(1.0, w.lpNorm<Eigen::Infinity>()));
  const double res = fc2d_natural_residual(p, z);
  EXPECT_EQ(res, std::stod(member(r.out, "residual")));
  EXPECT_LE(res, 1e-8 * std::max(1.0, p.q.lpNorm<Eigen::Infinity>()));
  return r.out;
}

TEST(LcpFc2dCli, SolvesEverySiconos2dFileWithNoOptions) {
  // Every 2D file of Siconos' test data (tests/data/fc2d, listed from the folder) by the
  // default route: prox-newton passes the solution test on each, the granular files whose W is
  // indefinite after Siconos' 6-digit print included (docs/lcp.md "The default route").
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(kData))
    if (e.path().extension() == ".dat") names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  ASSERT_GE(names.size(), 11u);
  for (const std::string& name : names) {
    const std::string out = expect_solved(name, "");
    const std::string route = member(out, "route");
    EXPECT_EQ(route.rfind("\"prox-newton", 0), 0u) << name << ": " << route;
  }
}

TEST(LcpFc2dCli, ANamedSolverRunsAloneAndSaysSo) {
  // --solver keeps its meaning: that solver, and the route is just its name.
  const std::string a = expect_solved("FrictionContactProblem00071.dat", "--solver newton");
  EXPECT_EQ(member(a, "route"), "\"newton\"");
  EXPECT_EQ(member(a, "solver"), "\"newton\"");
  const std::string b = expect_solved("FC2D_SliderCrankLagrangian00000.dat", "--solver newton-sparse --proximal");
  EXPECT_EQ(member(b, "route"), "\"proximal:newton-sparse\"");
}

TEST(LcpFc2dCli, KindIsDetectedOrForced) {
  const std::string f = kData + "FrictionContactProblem00394.dat";
  const test::CliResult lcp_forced = test::run_cli("lcp solve \"" + f + "\" --kind lcp");
  EXPECT_EQ(lcp_forced.exit_code, 1);
  EXPECT_EQ(lcp_forced.out, "");
  EXPECT_EQ(test::count_lines(lcp_forced.err), 1) << lcp_forced.err;
  const test::CliResult lcp = test::run_cli("lcp solve \"" + std::string(DC_SOURCE_DIR) + "/tests/data/lcp/small_spd.dat\"");
  EXPECT_EQ(member(lcp.out, "problem"), "\"lcp\"");
  EXPECT_EQ(lcp.out.find("\"mu\""), std::string::npos);
  EXPECT_NE(lcp.out.find("\"solve_seconds\""), std::string::npos);
}

TEST(LcpFc2dCli, SiconosToFclibToSiconosIsBitEqualAndSolvesTheSame) {
  test::TempDir dir;
  for (const char* name : {"FrictionContactProblem00071.dat", "fc2d_granularflowonwall_00667_00000.dat"}) {
    SCOPED_TRACE(name);
    const std::string h5 = dir / "p.hdf5", back = dir / "back.dat";
    ASSERT_EQ(test::run_cli("lcp convert \"" + kData + name + "\" " + h5).exit_code, 0);
    ASSERT_EQ(test::run_cli("lcp convert " + h5 + " " + back + " --format siconos-fc").exit_code, 0);
    const Fc2dProblem a = read_fc2d_dat(kData + name).problem;
    const ProblemFile fclib = read_problem_file(h5);
    const Fc2dProblem b = read_fc2d_dat(back).problem;
    for (const Fc2dProblem* x : {&fclib.fc2d, &b}) {
      EXPECT_EQ(Eigen::MatrixXd(x->W - a.W).cwiseAbs().maxCoeff(), 0.0);
      EXPECT_EQ(x->q, a.q);
      EXPECT_EQ(x->mu, a.mu);
    }
    const test::CliResult s1 = test::run_cli("lcp solve \"" + kData + name + "\" --solver newton");
    const test::CliResult s2 = test::run_cli("lcp solve " + h5 + " --solver newton");
    EXPECT_EQ(array_of(s1.out, "r"), array_of(s2.out, "r"));
  }
  // An LCP is not written as a frictional problem, nor a frictional one as an LCP.
  const test::CliResult e1 = test::run_cli("lcp convert \"" + std::string(DC_SOURCE_DIR) +
                                           "/tests/data/lcp/small_spd.dat\" " + (dir / "x.hdf5"));
  EXPECT_EQ(e1.exit_code, 1);
  EXPECT_EQ(test::count_lines(e1.err), 1) << e1.err;
  const test::CliResult e2 = test::run_cli("lcp convert \"" + kData + "FrictionContactProblem00394.dat\" " + (dir / "x.dat"));
  EXPECT_EQ(e2.exit_code, 1);
}

TEST(LcpFc2dCli, HostileFrictionalFilesGiveOneLineErrors) {
  test::TempDir dir;
  const std::string ok = "2\n1\n0\n2\n2\n2\t2\n2 0.5 0.5 3\n-1 0.5\n0.3\n";
  const std::string cases[] = {
      ok.substr(0, ok.size() - 5),                        // truncated
      "2\n3\n0\n6\n6\n6\t6\n2 0.5 0.5 3\n-1 0.5\n0.3\n",  // wrong counts
      "2\n1\n0\n2\n2\n2\t2\n2 nan 0.5 3\n-1 0.5\n0.3\n",  // NaN
      "2\n1\n0\n2\n2\n2\t2\n2 0.5 0.5 3\n-1 0.5\n-0.3\n",  // negative μ
      "3\n1\n0\n3\n3\n3\t3\n1 0 0 0 1 0 0 0 1\n-1 0 0\n0.3\n",  // dimension 3
      "2\n1\n2\n2\n2\n2\nCSparse\n2-by-2, nzmax: 9 nnz: 99999, 1-norm: 1\n",  // counts beyond the bytes
  };
  int k = 0;
  for (const std::string& text : cases) {
    const std::string path = dir / ("bad" + std::to_string(k++) + ".dat");
    { std::ofstream(path) << text; }
    const test::CliResult r = test::run_cli("lcp solve " + path + " --solver newton");
    EXPECT_EQ(r.exit_code, 1) << path << ": " << r.err;
    EXPECT_EQ(r.out, "") << path;
    EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("deepcontact: error: ", 0), 0u) << r.err;
  }
  const std::string junk = dir / "junk.hdf5";
  { std::ofstream(junk) << "\x89HDF\r\n\x1a\n garbage"; }
  const test::CliResult r = test::run_cli("lcp solve " + junk);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
}

TEST(LcpFc2dCli, SimulateExportsEachStepsProblemWithSolutionAndGuess) {
  test::TempDir dir;
  const std::string out = dir / "problems";
  const test::CliResult r =
      test::run_cli("simulate --steps 40 --export-problems " + out + " --every 20");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* step : {"step_000020.hdf5", "step_000040.hdf5"}) {
    SCOPED_TRACE(step);
    const ProblemFile f = read_problem_file(out + "/" + step);
    EXPECT_EQ(f.kind, ProblemKind::Fc2d);
    ASSERT_EQ(f.solution.size(), f.fc2d.q.size());
    ASSERT_EQ(f.guesses.size(), 1u);
    // The exported λ is the solver's answer: at the scene's tolerance, a near-solution.
    const double scale = std::max(1.0, f.fc2d.q.lpNorm<Eigen::Infinity>());
    EXPECT_LE(fc2d_natural_residual(f.fc2d, f.solution), 1e-2 * scale);
    // /solution/u is W r + q of the stored r.
    const FclibLocalProblem raw = read_fclib_local(out + "/" + step);
    const Eigen::VectorXd u = Eigen::Map<const Eigen::VectorXd>(raw.solution->u.data(), f.fc2d.q.size());
    EXPECT_LE((u - (f.fc2d.W * f.solution + f.fc2d.q)).lpNorm<Eigen::Infinity>(), 1e-12 * scale);
    const test::CliResult s = test::run_cli("lcp solve " + out + "/" + step + " --solver newton");
    EXPECT_EQ(s.exit_code, 0) << s.err;
    const test::CliResult d = test::run_cli("lcp solve " + out + "/" + step);  // the default route
    EXPECT_EQ(d.exit_code, 0) << d.err << d.out.substr(0, 200);
  }
  const test::CliResult dat =
      test::run_cli("simulate --steps 20 --export-problems " + out + " --every 20 --format siconos-fc");
  ASSERT_EQ(dat.exit_code, 0) << dat.err;
  EXPECT_EQ(read_problem_file(out + "/step_000020.dat").kind, ProblemKind::Fc2d);
}

}  // namespace
}  // namespace dc
