// FCLIB local problems (dc/lcp/fclib_file.hpp): round trip, compatibility with Debian's libfclib
// in both directions (when the tests are built with it: DC_HAVE_LIBFCLIB), and hostile files.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "dc/core/error.hpp"
#include "dc/lcp/fclib_file.hpp"
#include "dc/io/h5.hpp"

#ifdef DC_HAVE_LIBFCLIB
extern "C" {
#include <fclib.h>
}
#endif

namespace dc {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("dc_fclib_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

/// Two contacts, W = [[4,1,0,0.5],[1,3,0,0],[0,0,5,1],[0.5,0,1,2]] (column 2 misses row 3? no: full
/// pattern below), with a solution and two guesses.
FclibLocalProblem sample() {
  FclibLocalProblem p;
  p.rows = 4;
  p.col_start = {0, 3, 5, 7, 10};
  p.row_index = {0, 1, 3, 0, 1, 2, 3, 0, 2, 3};
  p.values = {4, 1, 0.5, 1, 3, 5, 1, 0.5, 1, 2};
  p.q = {-1, 0.25, -0.5, 1.0 / 3.0};
  p.mu = {0.5, 0.3};
  p.solution = FclibSolution{{0.25, 0.1, 0.1, 0}, {0, 0.2, 0, 0.4}};
  p.guesses = {FclibSolution{{1, 0, 0, 0}, {3, 1, 0, 1.5}}, FclibSolution{{0, 0, 2, 0}, {-1, 0.25, 9.5, 2.33}}};
  return p;
}

void expect_same(const FclibLocalProblem& a, const FclibLocalProblem& b) {
  EXPECT_EQ(a.rows, b.rows);
  EXPECT_EQ(a.col_start, b.col_start);
  EXPECT_EQ(a.row_index, b.row_index);
  EXPECT_EQ(a.values, b.values);
  EXPECT_EQ(a.q, b.q);
  EXPECT_EQ(a.mu, b.mu);
  ASSERT_EQ(a.solution.has_value(), b.solution.has_value());
  if (a.solution) {
    EXPECT_EQ(a.solution->r, b.solution->r);
    EXPECT_EQ(a.solution->u, b.solution->u);
  }
  ASSERT_EQ(a.guesses.size(), b.guesses.size());
  for (size_t g = 0; g < a.guesses.size(); ++g) {
    EXPECT_EQ(a.guesses[g].r, b.guesses[g].r);
    EXPECT_EQ(a.guesses[g].u, b.guesses[g].u);
  }
}

TEST(FclibFile, RoundTripIsBitExact) {
  const std::string path = temp_path("rt.hdf5");
  write_fclib_local(path, sample());
  expect_same(read_fclib_local(path), sample());
  FclibLocalProblem bare = sample();
  bare.solution.reset();
  bare.guesses.clear();
  write_fclib_local(path, bare);
  expect_same(read_fclib_local(path), bare);
  std::filesystem::remove(path);
  EXPECT_EQ(h5_open_object_count(), 0);
}

TEST(FclibFile, WriterRefusesInconsistentProblems) {
  FclibLocalProblem p = sample();
  p.mu[1] = -0.1;
  EXPECT_THROW(write_fclib_local(temp_path("x.hdf5"), p), InvalidArgument);
  p = sample();
  p.row_index[0] = 9;
  EXPECT_THROW(write_fclib_local(temp_path("x.hdf5"), p), InvalidArgument);
  p = sample();
  p.solution->r.pop_back();
  EXPECT_THROW(write_fclib_local(temp_path("x.hdf5"), p), InvalidArgument);
}

#ifdef DC_HAVE_LIBFCLIB
TEST(FclibFile, LibfclibReadsWhatWeWrite) {
  const std::string path = temp_path("ours.hdf5");
  const FclibLocalProblem p = sample();
  write_fclib_local(path, p);
  fclib_local* f = fclib_read_local(path.c_str());
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->spacedim, 2);
  EXPECT_EQ(f->W->m, 4);
  EXPECT_EQ(f->W->nz, -1);
  EXPECT_EQ(std::vector<int>(f->W->p, f->W->p + 5), p.col_start);
  EXPECT_EQ(std::vector<int>(f->W->i, f->W->i + 10), p.row_index);
  EXPECT_EQ(std::vector<double>(f->W->x, f->W->x + 10), p.values);
  EXPECT_EQ(std::vector<double>(f->q, f->q + 4), p.q);
  EXPECT_EQ(std::vector<double>(f->mu, f->mu + 2), p.mu);
  EXPECT_EQ(f->V, nullptr);
  fclib_delete_local(f);
  fclib_solution* s = fclib_read_solution(path.c_str());
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(std::vector<double>(s->r, s->r + 4), p.solution->r);
  EXPECT_EQ(std::vector<double>(s->u, s->u + 4), p.solution->u);
  fclib_delete_solutions(s, 1);
  int count = 0;
  fclib_solution* g = fclib_read_guesses(path.c_str(), &count);
  ASSERT_EQ(count, 2);
  EXPECT_EQ(std::vector<double>(g[1].r, g[1].r + 4), p.guesses[1].r);
  fclib_delete_solutions(g, count);
  std::filesystem::remove(path);
}

TEST(FclibFile, WeReadWhatLibfclibWrites) {
  const std::string path = temp_path("theirs.hdf5");
  std::filesystem::remove(path);
  FclibLocalProblem p = sample();
  fclib_matrix W{};
  W.nzmax = 10;
  W.m = W.n = 4;
  W.nz = -1;
  W.p = p.col_start.data();
  W.i = p.row_index.data();
  W.x = p.values.data();
  fclib_local f{};
  f.W = &W;
  f.q = p.q.data();
  f.mu = p.mu.data();
  f.spacedim = 2;
  ASSERT_EQ(fclib_write_local(&f, path.c_str()), 1);
  fclib_solution s{nullptr, p.solution->u.data(), p.solution->r.data(), nullptr};
  ASSERT_EQ(fclib_write_solution(&s, path.c_str()), 1);
  fclib_solution gs[2] = {{nullptr, p.guesses[0].u.data(), p.guesses[0].r.data(), nullptr},
                          {nullptr, p.guesses[1].u.data(), p.guesses[1].r.data(), nullptr}};
  ASSERT_EQ(fclib_write_guesses(2, gs, path.c_str()), 1);
  expect_same(read_fclib_local(path), p);
  // A triplet W (nz ≥ 0: CSparse's i = row, p = column) gives the same compressed columns.
  const std::string tpath = temp_path("triplet.hdf5");
  std::filesystem::remove(tpath);
  std::vector<int> rows, cols;
  for (int j = 0; j < 4; ++j)
    for (int k = p.col_start[static_cast<size_t>(j)]; k < p.col_start[static_cast<size_t>(j) + 1]; ++k) {
      rows.push_back(p.row_index[static_cast<size_t>(k)]);
      cols.push_back(j);
    }
  W.nz = 10;
  W.p = cols.data();
  W.i = rows.data();
  ASSERT_EQ(fclib_write_local(&f, tpath.c_str()), 1);
  FclibLocalProblem bare = p;
  bare.solution.reset();
  bare.guesses.clear();
  expect_same(read_fclib_local(tpath), bare);
  std::filesystem::remove(path);
  std::filesystem::remove(tpath);
}
#endif

/// Writes `sample()` and then lets `damage` change the file; reading must throw one line.
template <class Damage>
void expect_refused(const std::string& label, Damage damage, const std::string& needle) {
  SCOPED_TRACE(label);
  const std::string path = temp_path(label + ".hdf5");
  write_fclib_local(path, sample());
  {
    H5File f = H5File::open_rw(path);
    damage(f);
  }
  try {
    read_fclib_local(path);
    ADD_FAILURE() << "accepted";
  } catch (const IoError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_NE(m.find(needle), std::string::npos) << m;
  }
  std::filesystem::remove(path);
  EXPECT_EQ(h5_open_object_count(), 0);
}

void replace_ints(H5File& f, const std::string& path, const std::vector<std::int32_t>& v) {
  f.remove(path);
  f.write<std::int32_t>(path, v, {v.size()});
}
void replace_doubles(H5File& f, const std::string& path, const std::vector<double>& v) {
  f.remove(path);
  f.write<double>(path, v, {v.size()});
}

TEST(FclibFile, HostileFilesGiveOneLineErrors) {
  expect_refused("dim3", [](H5File& f) { replace_ints(f, "/fclib_local/spacedim", {3}); }, "spacedim 3");
  expect_refused("dim7", [](H5File& f) { replace_ints(f, "/fclib_local/spacedim", {7}); }, "spacedim 7");
  expect_refused("mixed", [](H5File& f) { f.create_group("/fclib_local/V"); }, "mixed");
  expect_refused("nolocal", [](H5File& f) { f.remove("/fclib_local"); }, "no /fclib_local");
  expect_refused("odd", [](H5File& f) { replace_ints(f, "/fclib_local/W/m", {3}); }, "not square");
  expect_refused("huge", [](H5File& f) {
    replace_ints(f, "/fclib_local/W/m", {2000000000});
    replace_ints(f, "/fclib_local/W/n", {2000000000});
  }, "rows");
  expect_refused("nzmax", [](H5File& f) { replace_ints(f, "/fclib_local/W/nzmax", {11}); }, "shape");
  expect_refused("nz", [](H5File& f) { replace_ints(f, "/fclib_local/W/nz", {-3}); }, "impossible");
  expect_refused("index", [](H5File& f) { replace_ints(f, "/fclib_local/W/i", {0, 1, 3, 0, 1, 2, 3, 0, 2, 4}); },
                 "out of range");
  expect_refused("twice", [](H5File& f) { replace_ints(f, "/fclib_local/W/i", {0, 0, 3, 0, 1, 2, 3, 0, 2, 3}); },
                 "twice");
  expect_refused("ptr", [](H5File& f) { replace_ints(f, "/fclib_local/W/p", {0, 3, 2, 7, 10}); }, "out of order");
  expect_refused("nan", [](H5File& f) { replace_doubles(f, "/fclib_local/W/x", {4, 1, 0.5, 1, NAN, 5, 1, 0.5, 1, 2}); },
                 "not finite");
  expect_refused("mu", [](H5File& f) { replace_doubles(f, "/fclib_local/vectors/mu", {0.5, -0.3}); }, "negative");
  expect_refused("qsize", [](H5File& f) { replace_doubles(f, "/fclib_local/vectors/q", {1, 2, 3}); }, "shape");
  expect_refused("guesses", [](H5File& f) { replace_ints(f, "/guesses/number_of_guesses", {3}); }, "missing");
  expect_refused("solution", [](H5File& f) { replace_doubles(f, "/solution/r", {1, 2}); }, "shape");
  // Not HDF5 at all, and a truncated file.
  const std::string junk = temp_path("junk.hdf5");
  { std::ofstream(junk) << "2\n1\n0\n"; }
  EXPECT_THROW(read_fclib_local(junk), IoError);
  write_fclib_local(junk, sample());
  std::filesystem::resize_file(junk, std::filesystem::file_size(junk) / 2);
  EXPECT_THROW(read_fclib_local(junk), IoError);
  std::filesystem::remove(junk);
  EXPECT_THROW(read_fclib_local(temp_path("missing.hdf5")), IoError);
}

}  // namespace
}  // namespace dc
