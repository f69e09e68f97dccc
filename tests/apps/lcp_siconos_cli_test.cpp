// `deepcontact lcp solve` / `lcp convert` on LCP files as Siconos writes them (docs/lcp.md):
// remarks after q come back as "comment" (and a note on stderr), sparse-block storage (1)
// solves like its dense twin, and every shipped problem ends solved (verified here from the
// file, independently of the solver), honestly failed, or infeasible with a named proof.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "apps/cli_helpers.hpp"
#include "dc/lcp/dat_file.hpp"

namespace dc {
namespace {

const std::string kData = std::string(DC_SOURCE_DIR) + "/tests/data/lcp/";

/// The members of the flat JSON object `lcp solve` prints: strings decoded, everything else raw.
std::map<std::string, std::string> json_members(const std::string& json) {
  std::map<std::string, std::string> out;
  size_t i = json.find('{');
  auto read_string = [&](size_t& k) {  // k at the opening quote; returns the decoded text
    std::string s;
    for (++k; k < json.size() && json[k] != '"'; ++k) {
      if (json[k] != '\\' || k + 1 >= json.size()) {
        s += json[k];
        continue;
      }
      const char e = json[++k];
      if (e == 'u' && k + 4 < json.size()) {
        s += static_cast<char>(std::stoi(json.substr(k + 1, 4), nullptr, 16));
        k += 4;
      } else {
        s += e == 'n' ? '\n' : e == 't' ? '\t' : e;
      }
    }
    ++k;
    return s;
  };
  while (i != std::string::npos && i < json.size()) {
    const size_t q = json.find('"', i);
    if (q == std::string::npos) break;
    size_t k = q;
    const std::string key = read_string(k);
    k = json.find(':', k) + 1;
    while (k < json.size() && json[k] == ' ') ++k;
    if (k < json.size() && json[k] == '"') {
      out[key] = read_string(k);
    } else {
      const size_t end = json[k] == '[' ? json.find(']', k) + 1 : json.find_first_of(",}", k);
      out[key] = json.substr(k, end - k);
      k = end;
    }
    i = json.find_first_of(",}", k);
    if (i != std::string::npos && json[i] == '}') break;
  }
  return out;
}

std::vector<double> numbers(std::string array) {
  std::replace(array.begin(), array.end(), ',', ' ');
  std::replace(array.begin(), array.end(), '[', ' ');
  std::replace(array.begin(), array.end(), ']', ' ');
  std::istringstream in(array);
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return v;
}

struct Solve {
  test::CliResult run;
  std::map<std::string, std::string> json;
  Eigen::VectorXd z;
};

Solve solve(const std::string& path, const std::string& solver) {
  Solve s;
  s.run = test::run_cli("lcp solve \"" + path + "\" --solver " + solver + " --sweeps 100000 --tol 1e-14");
  s.json = json_members(s.run.out);
  const std::vector<double> z = numbers(s.json["z"]);
  s.z = Eigen::Map<const Eigen::VectorXd>(z.data(), static_cast<Eigen::Index>(z.size()));
  return s;
}

TEST(LcpSiconosCli, RemarkAfterQIsReportedAsComment) {
  const std::string path = kData + "degenerate.dat";
  const Solve s = solve(path, "lemke");
  EXPECT_EQ(s.run.exit_code, 0) << s.run.out << s.run.err;
  EXPECT_EQ(s.json.at("status"), "converged");
  const std::string remark = read_dat_file(path).comment;
  ASSERT_FALSE(remark.empty());
  EXPECT_EQ(s.json.at("comment"), remark);
  EXPECT_NE(s.run.err.find("text after q was ignored"), std::string::npos) << s.run.err;
  EXPECT_EQ(test::count_lines(s.run.err), 1) << s.run.err;
  const Solve plain = solve(kData + "small_spd.dat", "lemke");
  EXPECT_EQ(plain.json.at("comment"), "");
  EXPECT_EQ(plain.run.err, "");
}

TEST(LcpSiconosCli, SparseBlockFileSolvesLikeItsDenseTwin) {
  for (const char* solver : {"lemke", "newton", "pgs"}) {
    const Solve sparse = solve(kData + "blocks_sparse.dat", solver), dense = solve(kData + "blocks_dense.dat", solver);
    EXPECT_EQ(sparse.run.exit_code, 0) << solver << ": " << sparse.run.out << sparse.run.err;
    EXPECT_EQ(sparse.json.at("status"), "converged") << solver;
    ASSERT_EQ(sparse.z.size(), 5) << sparse.run.out;
    EXPECT_EQ(sparse.z, dense.z) << solver;
    EXPECT_EQ(sparse.json.at("w"), dense.json.at("w")) << solver;
  }
}

TEST(LcpSiconosCli, ConvertWritesEitherStorage) {
  test::TempDir dir;
  const DatFile dense = read_dat_file(kData + "blocks_dense.dat");
  for (const char* block : {"1", "2", "0"}) {
    const std::string out = dir / (std::string("b") + block + ".dat");
    const test::CliResult r =
        test::run_cli("lcp convert \"" + kData + "blocks_dense.dat\" \"" + out + "\" --storage 1 --block " + block);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const DatFile f = read_dat_file(out);
    EXPECT_EQ(f.storage, DatStorage::SparseBlock);
    EXPECT_EQ(Eigen::MatrixXd(f.problem.A), Eigen::MatrixXd(dense.problem.A)) << block;
    EXPECT_EQ(f.problem.b, dense.problem.b);
    EXPECT_EQ(solve(out, "lemke").z, solve(kData + "blocks_dense.dat", "lemke").z) << block;
  }
  const std::string back = dir / "back.dat";
  ASSERT_EQ(test::run_cli("lcp convert \"" + kData + "blocks_sparse.dat\" \"" + back + "\" --storage 0").exit_code, 0);
  EXPECT_EQ(read_dat_file(back).storage, DatStorage::Dense);
  EXPECT_EQ(Eigen::MatrixXd(read_dat_file(back).problem.A), Eigen::MatrixXd(dense.problem.A));
  const test::CliResult noted = test::run_cli("lcp convert \"" + kData + "degenerate.dat\" \"" + back + "\"");
  EXPECT_EQ(noted.exit_code, 0);
  EXPECT_NE(noted.err.find("not copied"), std::string::npos) << noted.err;
  const test::CliResult bad = test::run_cli("lcp convert \"" + kData + "degenerate.dat\" \"" + back + "\" --storage 2");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(test::count_lines(bad.err), 1) << bad.err;
}

TEST(LcpSiconosCli, MalformedSparseBlockFileIsOneLineError) {
  test::TempDir dir;
  const std::string path = dir / "bad.dat";
  std::ofstream(path) << "2\n1\n2\n2\n2\n2\n2\n1\t2\t\n1\t2\t\n3\n2\n0\t1\t2\t\n0\t7\t\n0\n4\n1\n5\n-1 -1\n";
  const Solve s = solve(path, "lemke");
  EXPECT_EQ(s.run.exit_code, 1);
  EXPECT_EQ(s.run.out, "");
  EXPECT_EQ(test::count_lines(s.run.err), 1) << s.run.err;
  EXPECT_NE(s.run.err.find("bad.dat"), std::string::npos) << s.run.err;
  EXPECT_NE(s.run.err.find("block-column index 1 = 7"), std::string::npos) << s.run.err;
}

TEST(LcpSiconosCli, EveryShippedProblemIsSolvedOrHonestlyReported) {
  int files = 0, infeasible_files = 0;
  for (const auto& e : std::filesystem::directory_iterator(kData)) {
    if (e.path().extension() != ".dat") continue;
    ++files;
    const std::string path = e.path().string(), name = e.path().filename().string();
    const bool infeasible = name.rfind("infeasible", 0) == 0;  // the files that have no solution
    infeasible_files += infeasible;
    const LcpProblem p = read_lcp_dat(path);
    const double scale = std::max(1.0, p.b.cwiseAbs().maxCoeff());
    for (const char* solver : {"lemke", "newton"}) {
      Solve s = solve(path, solver);
      const std::string what = name + " " + solver + ": " + s.run.out;
      const std::string status = s.json["status"];
      EXPECT_EQ(s.run.exit_code, status == "converged" ? 0 : status == "infeasible" ? 3 : 1) << what;
      if (status == "converged") {  // verified here from the file: z >= 0, w >= 0, z'w = 0
        ASSERT_EQ(s.z.size(), p.rows()) << what;
        const Eigen::VectorXd w = Eigen::MatrixXd(p.A) * s.z + p.b;
        EXPECT_GE(s.z.minCoeff(), 0.0) << what;
        EXPECT_GE(w.minCoeff(), -1e-8 * scale) << what;
        EXPECT_LE(s.z.cwiseMin(w).cwiseAbs().maxCoeff(), 1e-8 * scale) << what;
        EXPECT_FALSE(infeasible) << what;
      } else if (status == "infeasible") {
        EXPECT_TRUE(infeasible) << what;
        const std::string& m = s.json["message"];
        EXPECT_TRUE(m.find("Farkas certificate") != std::string::npos ||
                    m.find("exhaustive enumeration") != std::string::npos)
            << "infeasible names its proof: " << what;
      } else {
        EXPECT_EQ(status, "failed") << what;
        EXPECT_FALSE(s.json["message"].empty()) << what;
      }
      // lemke decides every shipped problem: solved, or infeasible with a proof.
      if (std::string(solver) == "lemke") {
        EXPECT_EQ(status, infeasible ? "infeasible" : "converged") << what;
      }
    }
  }
  EXPECT_GE(files, 9);
  EXPECT_GE(infeasible_files, 3);
}

}  // namespace
}  // namespace dc
