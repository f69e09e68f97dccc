// Siconos .dat reader/writer: round trip, column-major layout, every malformed-file class.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dc/engine/dat_file.hpp"
#include "dc/engine/error.hpp"
#include "engine/solver_test_problems.hpp"

namespace dc {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("dc_dat_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

TEST(DatFile, RoundTripIsExact) {
  test::TestRng rng(1);
  for (int n : {1, 2, 7, 30}) {
    Eigen::MatrixXd M(n, n);
    Eigen::VectorXd q(n);
    for (int i = 0; i < n; ++i) {
      q[i] = rng.uniform(-1e3, 1e3) * std::pow(10.0, rng.uniform(-200, 200));
      for (int j = 0; j < n; ++j) M(i, j) = rng.uniform(-1, 1) / 3.0;
    }
    const std::string path = temp_path("rt.dat");
    write_lcp_dat(path, M, q);
    const LcpProblem p = read_lcp_dat(path);
    std::filesystem::remove(path);
    EXPECT_EQ(Eigen::MatrixXd(p.A), M);
    EXPECT_EQ(p.b, q);
    EXPECT_EQ(p.lo, Eigen::VectorXd::Zero(n));
    EXPECT_TRUE(std::isinf(p.hi[0]));
  }
}

TEST(DatFile, MatrixIsColumnMajorOneColumnPerLine) {
  // M = [[1, 2], [3, 4]] is written column by column: "1 3" then "2 4".
  const LcpProblem p = parse_lcp_dat("2\n0\n2\n2\n2\t2\n1 3 \n2 4 \n-1 -2 ", "mem");
  EXPECT_EQ(p.A.coeff(0, 1), 2.0);
  EXPECT_EQ(p.A.coeff(1, 0), 3.0);
  EXPECT_EQ(p.b[1], -2.0);
  EXPECT_NE(format_lcp_dat(Eigen::MatrixXd(p.A), p.b).find("1 3 \n2 4 \n"), std::string::npos);
}

TEST(DatFile, LiberalWithWhitespace) {
  const LcpProblem p = parse_lcp_dat("  2 0\r\n2 2 2 2 1.5e0 +3\t\t2\n\n4 -1 -2.5E-1\n\n", "mem");
  EXPECT_EQ(p.A.coeff(1, 0), 3.0);
  EXPECT_EQ(p.b[1], -0.25);
}

TEST(DatFile, ShippedExamplesParse) {
  for (const char* f : {"small_spd.dat", "infeasible.dat", "contact_12.dat"}) {
    const LcpProblem p = read_lcp_dat(std::string(DC_SOURCE_DIR) + "/tests/data/lcp/" + f);
    EXPECT_GT(p.rows(), 0) << f;
  }
}

void expect_io_error(const std::string& text, const std::string& needle) {
  try {
    (void)parse_lcp_dat(text, "bad.dat");
    ADD_FAILURE() << "no error for: " << text.substr(0, 60);
  } catch (const IoError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad.dat"), std::string::npos) << msg;
    EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "message must be one line: " << msg;
  }
}

TEST(DatFile, MalformedFilesThrowIoError) {
  const std::string head = "2\n0\n2\n2\n2\t2\n";
  expect_io_error("", "ends before");
  expect_io_error(head + "1 3\n2 4\n-1", "truncated");                      // q short
  expect_io_error(head + "1 3\n2", "too short");                            // M short
  expect_io_error(head + "1 3\n2 x\n-1 -2", "not a number");                // non-numeric
  expect_io_error(head + "1 3\n2 4\n-1 nan", "not finite");                 // NaN
  expect_io_error(head + "1 inf\n2 4\n-1 -2", "not finite");                // Inf
  expect_io_error(head + "1 3\n2 4\n-1 1e999", "out of the double range");  // overflow
  expect_io_error("0\n0\n0\n0\n0\t0\n", "must be positive");                // n = 0
  expect_io_error("-3\n0\n", "must be positive");                           // n < 0
  expect_io_error("2000000\n0\n2000000\n2000000\n2000000\t2000000\n1 2", "exceeds the limit");
  expect_io_error("90000\n0\n90000\n90000\n90000\t90000\n1 2 3", "too short");  // no huge allocation
  expect_io_error("2\n2\n2\n2\n1 3\n2 4\n-1 -2", "storage type 2");           // compressed sparse: not supported
  expect_io_error(head + "1 3\n2 4\n-1 -2x", "not a number");              // a remark glued to q is a bad number
  expect_io_error("2\n0\n2\n3\n2\t3\n1 3\n2 4\n-1 -2", "2x3");              // not square
  expect_io_error("2\n0\n2\n2\n2\t3\n1 3\n2 4\n-1 -2", "repeated size");    // inconsistent size line
  expect_io_error("2.5\n0\n", "integer");                                   // non-integer size
}

TEST(DatFile, MissingFileThrowsIoError) {
  EXPECT_THROW((void)read_lcp_dat("/nonexistent/dir/none.dat"), IoError);
  const std::string path = temp_path("empty.dat");
  std::ofstream(path).close();
  EXPECT_THROW((void)read_lcp_dat(path), IoError);
  std::filesystem::remove(path);
  EXPECT_THROW(write_lcp_dat("/nonexistent/dir/out.dat", Eigen::MatrixXd::Identity(1, 1), Eigen::VectorXd::Ones(1)),
               IoError);
}

}  // namespace
}  // namespace dc
