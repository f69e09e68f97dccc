// Problem files that are not regular files (docs/robustness.md "Readers that refuse damage"):
// a FIFO that no process writes is refused at once with one line (opening it blocking would wait
// forever for a writer), and a pipe with a writer is read whole, its first bytes included (the HDF5
// signature check must not consume them).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "apps/cli_helpers.hpp"
#include "temp_dir.hpp"

namespace dc {
namespace {

const std::string kData = std::string(DC_SOURCE_DIR) + "/tests/data/lcp/";

TEST(FifoCli, AFifoWithoutAWriterIsRefusedAtOnce) {
  const test::TempDir dir;
  const std::string fifo = dir / "problem.dat";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // Watchdog: should the reader block in open(), a writer that opens and closes the FIFO
  // releases it (the reader then sees end of file) and the elapsed time fails the test.
  std::atomic<bool> done{false};
  std::thread watchdog([&] {
    for (int i = 0; i < 300 && !done; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (done) return;
    const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
    if (fd >= 0) ::close(fd);
  });
  const auto t0 = std::chrono::steady_clock::now();
  const test::CliResult r = test::run_cli("lcp solve \"" + fifo + "\"");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  done = true;
  watchdog.join();
  EXPECT_LT(seconds, 20.0) << "the reader waited for a writer";
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(fifo), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("FIFO"), std::string::npos) << r.err;
}

TEST(FifoCli, APipeWithAWriterIsReadWhole) {
  const std::string file = kData + "small_spd.dat";
  const test::CliResult direct = test::run_cli("lcp solve \"" + file + "\" --solver lemke");
  ASSERT_EQ(direct.exit_code, 0) << direct.err;
  const std::string cmd = "cat \"" + file + "\" | " + std::string(DC_CLI) + " lcp solve /dev/stdin --solver lemke 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  std::array<char, 4096> buf{};
  for (std::size_t n; (n = std::fread(buf.data(), 1, buf.size(), p)) > 0;) out.append(buf.data(), n);
  const int status = ::pclose(p);
  ASSERT_TRUE(WIFEXITED(status)) << out;
  EXPECT_EQ(WEXITSTATUS(status), 0) << out;
  // The same solution as from the regular file (the JSON names the file, so compare z only).
  const auto z_of = [](const std::string& json) {
    const auto at = json.find("\"z\"");
    return at == std::string::npos ? std::string() : json.substr(at, json.find(']', at) - at);
  };
  EXPECT_FALSE(z_of(direct.out).empty()) << direct.out;
  EXPECT_EQ(z_of(out), z_of(direct.out)) << out;
}

}  // namespace
}  // namespace dc
