// WorkTeam: every job runs once whatever the thread count, gather runs member 0 on the calling
// thread and each helper at most once per run, exceptions reach the caller, a nested run is
// serial, and runs follow each other without a helper ever seeing a finished run's body.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include "dc/core/work_team.hpp"

namespace dc {
namespace {

TEST(WorkTeam, ForPartsRunsEveryJobOnce) {
  WorkTeam team;
  for (const int threads : {1, 2, 3, 8, 70}) {  // 70: more than a team's 64 members
    for (const int parts : {0, 1, 2, 7, 100, 300}) {
      std::vector<std::atomic<int>> runs(static_cast<size_t>(parts));
      team.for_parts(threads, parts, [&](int p) { runs[static_cast<size_t>(p)].fetch_add(1); });
      for (int p = 0; p < parts; ++p) EXPECT_EQ(1, runs[static_cast<size_t>(p)].load()) << threads << " " << parts;
    }
  }
}

TEST(WorkTeam, GatherRunsMemberZeroOnTheCallerAndEachHelperAtMostOnce) {
  WorkTeam team;
  const std::thread::id caller = std::this_thread::get_id();
  for (int run = 0; run < 200; ++run) {
    std::atomic<int> seen[3] = {0, 0, 0};
    std::atomic<bool> zero_on_caller{false};
    team.gather(3, [&](int m) {
      seen[m].fetch_add(1);
      if (m == 0) zero_on_caller = std::this_thread::get_id() == caller;
    });
    EXPECT_EQ(1, seen[0].load());
    EXPECT_TRUE(zero_on_caller.load());
    EXPECT_LE(seen[1].load(), 1);
    EXPECT_LE(seen[2].load(), 1);
  }
}

TEST(WorkTeam, AJobsExceptionReachesTheCaller) {
  WorkTeam team;
  EXPECT_THROW(team.for_parts(2, 64, [](int p) { if (p == 40) throw std::runtime_error("job 40"); }),
               std::runtime_error);
  // The team works on after a throw.
  std::atomic<int> sum{0};
  team.for_parts(2, 10, [&](int p) { sum.fetch_add(p); });
  EXPECT_EQ(45, sum.load());
}

TEST(WorkTeam, NestedRunsAreSerialAndComplete) {
  WorkTeam team;
  std::atomic<int> inner{0};
  team.for_parts(2, 4, [&](int) { calling_thread_team().for_parts(2, 5, [&](int) { inner.fetch_add(1); }); });
  EXPECT_EQ(20, inner.load());
}

TEST(WorkTeam, ManyShortRunsEachCompleteBeforeTheNext) {
  WorkTeam team;
  long total = 0;
  for (int run = 0; run < 2000; ++run) {
    std::vector<int> out(16, 0);  // a run's outputs live only for that run
    team.for_parts(2, 16, [&](int p) { out[static_cast<size_t>(p)] = p + run; });
    for (int p = 0; p < 16; ++p) total += out[static_cast<size_t>(p)] - run;
  }
  EXPECT_EQ(2000L * 120, total);
}

// A child of fork() inherits a team whose helpers are the parent's threads, which do not exist
// there: its runs must still complete (the calling thread does every job) and ending the team
// must not hang on the parent's helpers.
TEST(WorkTeam, ForkedChildRunsEveryJobAndEndsItsTeam) {
  auto team = std::make_unique<WorkTeam>();
  std::atomic<int> before{0};
  team->for_parts(3, 64, [&](int) { before.fetch_add(1); });
  ASSERT_EQ(64, before.load());
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::alarm(60);  // a hang becomes a death by SIGALRM, which the parent reports
    std::atomic<int> runs{0};
    for (int round = 0; round < 50; ++round) team->for_parts(3, 64, [&](int) { runs.fetch_add(1); });
    team.reset();
    ::_exit(runs.load() == 50 * 64 ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(child, ::waitpid(child, &status, 0));
  ASSERT_TRUE(WIFEXITED(status)) << "the child did not exit (signal " << WTERMSIG(status) << ")";
  EXPECT_EQ(0, WEXITSTATUS(status));
  std::atomic<int> after{0};
  team->for_parts(3, 64, [&](int) { after.fetch_add(1); });
  EXPECT_EQ(64, after.load());
}

TEST(WorkTeam, TheTraceHasOneOrderedRecordPerThreadedRun) {
  WorkTeam team;
  std::vector<TeamRunTrace> trace;
  team.set_trace(&trace);
  for (int run = 0; run < 20; ++run) team.for_parts(2, 8, [](int) {});
  team.for_parts(1, 8, [](int) {});  // serial: not a team run
  team.set_trace(nullptr);
  team.for_parts(2, 8, [](int) {});
  ASSERT_EQ(20U, trace.size());
  for (const TeamRunTrace& t : trace) {
    EXPECT_LE(t.publish, t.caller_done);
    EXPECT_LE(t.caller_done, t.end);
    if (t.helper_start >= 0) {
      EXPECT_LE(t.publish, t.helper_start);
      EXPECT_LE(t.helper_start, t.helper_done);
      EXPECT_LE(t.helper_done, t.end);
    }
  }
}

}  // namespace
}  // namespace dc
