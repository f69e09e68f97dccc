// ThetaRows (theta_rows.hpp): the bench's θ rows kept in a nameless scratch file read back
// exactly, joined in order whether the parts share the file or not, from several threads.
#include <gtest/gtest.h>

#include <filesystem>
#include <thread>
#include <vector>

#include "dc/bench/theta_rows.hpp"
#include "dc/core/error.hpp"
#include "temp_dir.hpp"

namespace dc::bench {
namespace {

std::vector<float> row(int i, std::size_t n) {
  std::vector<float> r(n);
  for (std::size_t k = 0; k < n; ++k) r[k] = static_cast<float>(i) + 1e-3f * static_cast<float>(k);
  return r;
}

TEST(ThetaRows, RowsReadBackExactlyAndJoinInOrder) {
  test::TempDir dir;
  const auto shared = std::make_shared<ScratchFile>(dir.path().string());
  ThetaRows a(shared), b(shared), c(std::make_shared<ScratchFile>(dir.path().string()));
  for (int i = 0; i < 3; ++i) a.append(row(i, 5));
  for (int i = 3; i < 5; ++i) b.append(row(i, 5));
  for (int i = 5; i < 7; ++i) c.append(row(i, 5));
  a.append(b);  // same file: offsets only
  a.append(c);  // another file: copied
  ASSERT_EQ(a.rows(), 7u);
  std::vector<float> want;
  for (int i = 0; i < 7; ++i) for (const float v : row(i, 5)) want.push_back(v);
  EXPECT_EQ(a.all(), want);
  std::vector<float> part(2);
  a.read_row(4, part, 3);
  EXPECT_EQ(part, (std::vector<float>{want[4 * 5 + 3], want[4 * 5 + 4]}));
  EXPECT_THROW(a.read_row(7, part), IoError);
  EXPECT_THROW(a.read_row(0, part, 4), IoError);
  EXPECT_THROW(a.append(row(9, 4)), IoError);  // another length
  // Nameless: nothing of the scratch files is left in the folder.
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(ThetaRows, ThreadsSharingOneFileKeepTheirOwnRows) {
  const auto shared = std::make_shared<ScratchFile>();
  std::vector<ThetaRows> per_thread(4, ThetaRows(shared));
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] { for (int i = 0; i < 200; ++i) per_thread[t].append(row(1000 * t + i, 64)); });
  for (auto& th : threads) th.join();
  std::vector<float> got(64);
  for (int t = 0; t < 4; ++t) {
    ASSERT_EQ(per_thread[t].rows(), 200u);
    for (int i = 0; i < 200; ++i) {
      per_thread[t].read_row(static_cast<std::size_t>(i), got);
      ASSERT_EQ(got, row(1000 * t + i, 64)) << "thread " << t << " row " << i;
    }
  }
}

TEST(ScratchFile, AnUnwritableFolderIsAOneLineError) {
  try {
    ScratchFile f("/nonexistent/folder");
    ADD_FAILURE() << "made a scratch file in a missing folder";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/folder"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dc::bench
