// Siconos .dat reader/writer: round trip, column-major layout, every malformed-file class,
// remarks after q, sparse-block storage (type 1).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dc/core/error.hpp"
#include "dc/lcp/dat_file.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "lcp/solver_test_problems.hpp"

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
  const LcpProblem p = parse_lcp_dat("2\n0\n2\n2\n2\t2\n1 3 \n2 4 \n-1 -2 \n", "mem");
  EXPECT_EQ(p.A.coeff(0, 1), 2.0);
  EXPECT_EQ(p.A.coeff(1, 0), 3.0);
  EXPECT_EQ(p.b[1], -2.0);
  EXPECT_NE(format_lcp_dat(Eigen::MatrixXd(p.A), Eigen::VectorXd(p.b)).find("1 3 \n2 4 \n"), std::string::npos);
}

TEST(DatFile, LiberalWithWhitespace) {
  const LcpProblem p = parse_lcp_dat("  2 0\r\n2 2 2 2 1.5e0 +3\t\t2\n\n4 -1 -2.5E-1\n\n", "mem");
  EXPECT_EQ(p.A.coeff(1, 0), 3.0);
  EXPECT_EQ(p.b[1], -0.25);
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

const std::string kData = std::string(DC_SOURCE_DIR) + "/tests/data/lcp/";

// Files as Siconos writes them: remarks after q, sparse-block storage (type 1) equal to the
// dense twin, and every malformed sparse-block header class.

TEST(DatSiconos, RemarkAfterQIsKeptAsComment) {
  const std::string head = "2\n0\n2\n2\n2\t2\n1 3\n2 4\n-1 -2";
  const DatFile f = parse_dat_file(head + "\n\nRemark 4.1 (a book)\nset of solutions: z_1 + z_2 = 1\n\n", "mem");
  EXPECT_EQ(f.comment, "Remark 4.1 (a book)\nset of solutions: z_1 + z_2 = 1");
  EXPECT_EQ(f.problem.b[1], -2.0);
  EXPECT_EQ(f.storage, DatStorage::Dense);
  EXPECT_EQ(parse_dat_file(head + "  \n", "mem").comment, "");
  EXPECT_EQ(parse_dat_file(head + " 7 8\n", "mem").comment, "7 8");  // Siconos stops after q, so do we
  // Invalid UTF-8 and control characters become '?', valid UTF-8 stays; the length is capped.
  EXPECT_EQ(parse_dat_file(head + " Cottle\xe2\x80\x93Pang \xff\x01!\n", "mem").comment, "Cottle\xe2\x80\x93Pang ?\?!");
  EXPECT_EQ(parse_dat_file(head + " " + std::string(10000, 'x') + "\n", "mem").comment.size(), kMaxDatComment);
  // Malformed numbers before the end of q stay errors.
  expect_io_error("2\n0\n2\n2\n2\t2\n1 3\n2 4\n-1 Remark", "entry 1 of q is not a number");
  expect_io_error("2\n0\n2\n2\n2\t2\n1 3\n2 Remark -1 -2", "not a number");
}

TEST(DatSiconos, SparseBlockFileEqualsItsDenseTwin) {
  const DatFile sparse = read_dat_file(kData + "blocks_sparse.dat");
  const DatFile dense = read_dat_file(kData + "blocks_dense.dat");
  EXPECT_EQ(sparse.storage, DatStorage::SparseBlock);
  EXPECT_EQ(dense.storage, DatStorage::Dense);
  EXPECT_EQ(Eigen::MatrixXd(sparse.problem.A), Eigen::MatrixXd(dense.problem.A));
  EXPECT_EQ(sparse.problem.b, dense.problem.b);
  EXPECT_EQ(sparse.problem.A.nonZeros(), dense.problem.A.nonZeros());  // zeros are not stored
  EXPECT_EQ(sparse.problem.A.coeff(1, 2), 0.5);  // block 1 = rows 0–1 × columns 2–4, column-major
  EXPECT_EQ(sparse.problem.A.coeff(4, 3), 2.0);
  EXPECT_EQ(sparse.problem.A.coeff(3, 0), 0.0);  // block (1, 0) is not stored
  for (const char* name : {"lemke", "newton", "pgs"}) {
    SolverOptions o;
    o.max_sweeps = 100000;
    o.tolerance = 1e-14;
    const SolveResult a = make_solver(name)->solve(sparse.problem, Eigen::VectorXd(), o);
    const SolveResult b = make_solver(name)->solve(dense.problem, Eigen::VectorXd(), o);
    EXPECT_EQ(a.status, SolveStatus::Converged) << name << ": " << a.message;
    EXPECT_EQ(a.lambda, b.lambda) << name;  // same problem, same arithmetic
    EXPECT_LT(a.residual, 1e-9) << name;
  }
}

TEST(DatSiconos, SparseBlockWriterRoundTripsForEveryBlockSize) {
  test::TestRng rng(7);
  for (int n : {1, 5, 9}) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd q(n);
    for (int i = 0; i < n; ++i) {
      q[i] = rng.uniform(-1, 1);
      for (int j = 0; j < n; ++j)
        if (rng.uniform() < 0.4 || i == j) M(i, j) = rng.uniform(-1, 1) / 3.0;
    }
    if (n > 3) M.bottomRows(2).setZero();  // trailing empty block rows: filled1 < block rows + 1
    const SparseRowMatrix S = M.sparseView(0.0, 0.0);
    for (int b : {1, 2, 3, n}) {
      const std::string text = format_lcp_dat_blocks(S, q, b);
      const DatFile f = parse_dat_file(text, "mem");
      EXPECT_EQ(f.storage, DatStorage::SparseBlock);
      EXPECT_EQ(Eigen::MatrixXd(f.problem.A), M) << "n " << n << " block " << b << "\n" << text;
      EXPECT_EQ(f.problem.b, q);
      EXPECT_EQ(f.comment, "");
    }
  }
  // A zero matrix is "0" blocks and nothing else, as SBM_write_in_file writes it.
  const DatFile zero = parse_dat_file(format_lcp_dat_blocks(SparseRowMatrix(3, 3), Eigen::Vector3d(1, 2, 3), 2), "mem");
  EXPECT_EQ(zero.problem.A.nonZeros(), 0);
  EXPECT_EQ(zero.problem.b[2], 3.0);
  EXPECT_THROW((void)format_lcp_dat_blocks(SparseRowMatrix(2, 2), Eigen::Vector3d::Zero(), 1), InvalidArgument);
  EXPECT_THROW((void)format_lcp_dat_blocks(SparseRowMatrix(2, 2), Eigen::Vector2d::Zero(), 0), InvalidArgument);
}

TEST(DatSiconos, MalformedSparseBlockFilesThrowIoError) {
  // n = 2, two 1×1 block rows and columns, blocks (0,0) and (1,1).
  const std::string h = "2\n1\n2\n2\n";
  const std::string good = h + "2\n2\n2\n1\t2\t\n1\t2\t\n3\n2\n0\t1\t2\t\n0\t1\t\n0\n4\n1\n5\n-1 -1\n";
  EXPECT_EQ(Eigen::MatrixXd(parse_lcp_dat(good, "mem").A), (Eigen::MatrixXd(2, 2) << 4, 0, 0, 5).finished());
  std::string pad;  // enough numbers after a header error that no "too short" check fires first
  for (int i = 0; i < 30; ++i) pad += " 0";
  auto bad = [&](const std::string& text, const std::string& needle) { expect_io_error(text + pad, needle); };
  bad(h + "-1\n", "negative");
  bad(h + "2\n3\n2\n", "block grid 3x2");                                   // more block rows than n
  bad(h + "5\n2\n2\n", "do not fit");                                       // 5 blocks in 2x2
  bad(h + "2\n2\n2\n1\t1\t\n", "cumulative");                               // not increasing
  bad(h + "2\n2\n2\n1\t3\t\n", "at most n");                                // beyond n
  bad(h + "2\n1\n2\n1\t\n1\t2\t\n2\n2\n0\t2\t\n0\t1\t\n", "add up to 1");  // sizes ≠ n
  bad(h + "2\n2\n2\n1\t2\t\n1\t2\t\n4\n2\n", "filled1");                   // too many row pointers
  bad(h + "2\n2\n2\n1\t2\t\n1\t2\t\n3\n1\n", "filled2");                   // ≠ number of blocks
  bad(h + "2\n2\n2\n1\t2\t\n1\t2\t\n3\n2\n1\t1\t2\t\n0\t1\t\n", "row pointer 0");
  bad(h + "2\n2\n2\n1\t2\t\n1\t2\t\n3\n2\n0\t2\t1\t\n0\t1\t\n", "row pointer 2");
  bad(h + "2\n2\n2\n1\t2\t\n1\t2\t\n3\n2\n0\t1\t1\t\n0\t1\t\n", "last row pointer");
  bad(h + "2\n2\n2\n1\t2\t\n1\t2\t\n3\n2\n0\t1\t2\t\n0\t2\t\n", "block-column index 1 = 2");
  bad(h + "2\n2\n2\n1\t2\t\n1\t2\t\n3\n2\n0\t2\t2\t\n1\t1\t\n0\n4\n1\n5\n-1 -1", "given twice");
  bad(h + "2\n2\n2\n1\t2\t\n1\t2\t\n3\n2\n0\t1\t2\t\n0\t1\t\n1\n4\n0\n5\n-1 -1", "block number 1");
  bad(h + "2\n2\n2\n1\t2\t\n1\t2\t\n3\n2\n0\t1\t2\t\n0\t1\t\n0\n4\n1\nx\n-1 -1", "entry 0 of block 1");
  expect_io_error(h + "2\n2\n2\n1\t2\t\n1\t2\t\n3\n2\n0\t1\t2\t\n0\t1\t\n0\n4\n1\n5\n-1", "truncated");
  // Sizes the file cannot hold are refused before anything of that size is allocated.
  expect_io_error("90000\n1\n90000\n90000\n1\n1\n1\n90000\n90000\n2\n1\n0 1\n0\n0\n1 2", "too short");
  expect_io_error("90000\n1\n90000\n90000\n8000000000\n90000\n90000\n", "too short");
  expect_io_error("3\n1\n3\n2\n", "3x2");  // not square
}

TEST(DatSiconos, EveryShippedExampleParses) {
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(kData)) {
    if (e.path().extension() != ".dat") continue;
    ++files;
    const DatFile f = read_dat_file(e.path().string());
    EXPECT_GT(f.problem.rows(), 0) << e.path();
    EXPECT_NO_THROW(f.problem.validate()) << e.path();
  }
  EXPECT_GE(files, 9);
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
