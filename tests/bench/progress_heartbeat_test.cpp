// Without a terminal the progress bar prints plain heartbeat lines (a long run to a log file
// was silent for over a minute): each names the label, the progress and the ETA.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "dc/bench/progress_bar.hpp"

namespace dc {
namespace {

TEST(ProgressHeartbeat, WithoutATerminalPrintsPlainLines) {
  testing::internal::CaptureStderr();
  {
    bench::ProgressBar bar("bench", 4, /*enabled=*/false, std::chrono::milliseconds(0));
    bar.advance(1, "seed 1 step 1");
    bar.advance(1);
  }
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("bench: 1/4 (25%)"), std::string::npos) << err;
  EXPECT_NE(err.find("seed 1 step 1"), std::string::npos) << err;
  EXPECT_NE(err.find("bench: 2/4 (50%)"), std::string::npos) << err;
  EXPECT_EQ(err.find('\r'), std::string::npos) << err;  // no carriage-return bar in a log
}

TEST(ProgressHeartbeat, AShortRunPrintsNothing) {
  testing::internal::CaptureStderr();
  {
    bench::ProgressBar bar("bench", 3, /*enabled=*/false);  // heartbeat every 5 s
    bar.advance(3);
  }
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

}  // namespace
}  // namespace dc
