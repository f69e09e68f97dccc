// The problem readers refuse damage and the writers refuse what the readers refuse: every cut
// of a file is an error or the whole file's problem (never another value); sizes that overflow;
// endless devices; duplicated triplets; FCLIB data that is not in the file; NaN and n = 0 in
// the writers.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "dc/lcp/dat_file.hpp"
#include "dc/lcp/fc2d_dat_file.hpp"
#include "dc/lcp/fclib_file.hpp"
#include "dc/lcp/problem_file.hpp"
#include "io/io_error.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;
const std::string kData = std::string(DC_SOURCE_DIR) + "/tests/data/";

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string temp_path(const std::string& name) {
  return (fs::temp_directory_path() / ("dc_hostile_reader_" + std::to_string(::getpid()) + "_" + name)).string();
}

/// A one-line IoError message.
void expect_one_line(const std::string& message) {
  EXPECT_FALSE(message.empty());
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

// A file cut at any byte either fails to read or reads as the whole file: before, a cut inside
// the last number (μ 0.9 → 9) was read with the changed value.
TEST(HostileReader, EveryCutOfADatFileIsRefusedOrReadsTheWholeProblem) {
  for (const char* name : {"lcp/small_spd.dat", "lcp/blocks_sparse.dat", "lcp/contact_12.dat"}) {
    SCOPED_TRACE(name);
    const std::string text = slurp(kData + name);
    ASSERT_EQ(text.back(), '\n');
    const DatFile whole = parse_dat_file(text, name);
    for (size_t cut = 1; cut < text.size(); ++cut) {
      try {
        const DatFile part = parse_dat_file(std::string_view(text).substr(0, cut), name);
        EXPECT_EQ(Eigen::MatrixXd(part.problem.A), Eigen::MatrixXd(whole.problem.A)) << "cut " << cut;
        EXPECT_EQ(part.problem.b, whole.problem.b) << "cut " << cut;
      } catch (const IoError& e) {
        expect_one_line(e.what());
      }
    }
    EXPECT_THROW(parse_dat_file(std::string_view(text).substr(0, text.size() - 1), name), IoError);
  }
  for (const char* name : {"fc2d/FC2D_SliderCrankLagrangian00000.dat", "fc2d/FrictionContactProblem00031.dat"}) {
    SCOPED_TRACE(name);
    const std::string text = slurp(kData + name);
    ASSERT_EQ(text.back(), '\n');
    const Fc2dDatFile whole = parse_fc2d_dat(text, name);
    for (size_t cut = 1; cut < text.size(); ++cut) {
      try {
        const Fc2dDatFile part = parse_fc2d_dat(std::string_view(text).substr(0, cut), name);
        EXPECT_EQ(Eigen::MatrixXd(part.problem.W), Eigen::MatrixXd(whole.problem.W)) << "cut " << cut;
        EXPECT_EQ(part.problem.q, whole.problem.q) << "cut " << cut;
        EXPECT_EQ(part.problem.mu, whole.problem.mu) << "cut " << cut;
      } catch (const IoError& e) {
        expect_one_line(e.what());
      }
    }
  }
}

TEST(HostileReader, ALastNumberWithoutALineEndIsRefusedAsTruncated) {
  const std::string msg = test::io_error([] { parse_fc2d_dat("2\n1\n0\n2\n2\n2\t2\n1 0\n0 1\n-1 0\n0.9", "cut.dat"); });
  EXPECT_NE(msg.find("cut.dat: line 10: the last friction coefficient mu is not followed by a line end"),
            std::string::npos) << msg;
  EXPECT_NE(test::io_error([] { parse_dat_file("1\n0\n1\n1\n1\t1\n2\n-1", "cut.dat"); }).find("last entry of q"),
            std::string::npos);
  EXPECT_NO_THROW(parse_dat_file("1\n0\n1\n1\n1\t1\n2\n-1 \n", "whole.dat"));
  EXPECT_NO_THROW(parse_dat_file("1\n0\n1\n1\n1\t1\n2\n-1\nremark without a line end", "remark.dat"));
}

// Before: 2·nc wrapped past the size check and the reader tried to allocate it.
TEST(HostileReader, HugeContactCountsAreRefusedWithoutOverflow) {
  const std::string big = std::to_string(std::numeric_limits<long long>::max());
  const std::string msg = test::io_error([&] { parse_fc2d_dat("2\n" + big + "\n0\n-2\n-2\n", "big.dat"); });
  EXPECT_NE(msg.find("exceeds the limit"), std::string::npos) << msg;
  // detect_dat_kind multiplies d·nc: checked (UBSan would flag a wrap), so the header is
  // neither kind.
  const std::string kind = test::io_error([&] { detect_dat_kind("2\n" + big + "\n0\n-2\n-2\n", "big.dat"); });
  EXPECT_NE(kind.find("big.dat: not a Siconos LCP"), std::string::npos) << kind;
}

TEST(HostileReader, AnEndlessDeviceIsReadUpToTheCapAndRefused) {
  if (!fs::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
  const std::string msg = test::io_error([] { read_problem_file("/dev/zero"); });
  EXPECT_NE(msg.find("/dev/zero: not a regular file and longer than 256 MiB"), std::string::npos) << msg;
  expect_one_line(msg);
}

TEST(HostileReader, ACsparseTripletGivenTwiceIsRefusedWithItsRowAndColumn) {
  const std::string text = "2\n1\n2\n2\n2\n1\nCSparse Version 3.1.9\ntriplet: 2-by-2, nzmax: 3 nnz: 3\n"
                           "    0 0 : 2\n    1 1 : 3\n    0 0 : 1\n-1 0.5\n0.3\n";
  const std::string msg = test::io_error([&] { parse_fc2d_dat(text, "dup.dat"); });
  EXPECT_NE(msg.find("entry (0,0) is given twice"), std::string::npos) << msg;
  // Its header also fits a 2×2 LCP: neither kind reads it, and the message is the fc2d one,
  // the kind that read further.
  const std::string path = temp_path("dup.dat");
  std::ofstream(path) << text;
  const std::string via_file = test::io_error([&] { read_problem_file(path); });
  EXPECT_NE(via_file.find("entry (0,0) is given twice"), std::string::npos) << via_file;
  fs::remove(path);
}

TEST(HostileReader, WritersRefuseWhatTheReadersRefuse) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd M = Eigen::MatrixXd::Identity(2, 2);
  Eigen::VectorXd q(2);
  q << -1, nan;
  EXPECT_THROW(format_lcp_dat(M, q), InvalidArgument);
  EXPECT_THROW(format_lcp_dat(Eigen::MatrixXd(0, 0), Eigen::VectorXd(0)), InvalidArgument);
  q[1] = 1;
  M(1, 0) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(format_lcp_dat(M, q), InvalidArgument);
  EXPECT_THROW(format_lcp_dat_blocks(M.sparseView(), q, 1), InvalidArgument);
  EXPECT_THROW(format_lcp_dat_blocks(SparseRowMatrix(0, 0), Eigen::VectorXd(0), 1), InvalidArgument);
  M(1, 0) = 0;
  EXPECT_NO_THROW(parse_dat_file(format_lcp_dat(M, q), "ok.dat"));
  // An FCLIB solution with NaN: refused, and no file appears.
  Fc2dProblem p;
  p.W = M.sparseView();
  p.q = q;
  p.mu = Eigen::VectorXd::Constant(1, 0.5);
  const std::string out = temp_path("nan_solution.hdf5");
  EXPECT_THROW(write_fc2d_problem(out, p, ProblemFormat::Fclib, Eigen::Vector2d(nan, 0), {}), InvalidArgument);
  EXPECT_FALSE(fs::exists(out));
}

// Before: a q that was a virtual dataset with a missing source read as zeros ("converged").
TEST(HostileReader, FclibDataInOtherFilesIsRefusedNamingTheDataset) {
  Fc2dProblem p;
  p.W = Eigen::MatrixXd::Identity(2, 2).sparseView();
  p.q = Eigen::Vector2d(-1, 0);
  p.mu = Eigen::VectorXd::Constant(1, 0.5);
  const std::string path = temp_path("virtual_q.hdf5");
  write_fc2d_problem(path, p, ProblemFormat::Fclib, Eigen::VectorXd(), {});
  ASSERT_NO_THROW(read_problem_file(path));
  {
    H5File f = H5File::open_rw(path);
    f.remove("/fclib_local/vectors/q");
    f.create_virtual<double>("/fclib_local/vectors/q", {}, {{"missing_source.h5", "/q", 2}});
    f.close();
  }
  const std::string msg = test::io_error([&] { read_problem_file(path); });
  EXPECT_NE(msg.find("/fclib_local/vectors/q: is a virtual dataset"), std::string::npos) << msg;
  expect_one_line(msg);
  fs::remove(path);
}

}  // namespace
}  // namespace dc
