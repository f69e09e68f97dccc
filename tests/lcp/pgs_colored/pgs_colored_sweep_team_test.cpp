// pgs-colored's threaded sweeps (sweep_team.hpp): region_cuts gives each thread one region of
// the bodies in every colour, and the SweepTeam's threads sweep every batch of every range
// exactly once per sweep with those blocks (odd blocks from the back, thieves from the other
// end); a small colour is swept by thread 0 alone, after the colour before it and before the
// colour after it.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "solvers/pgs_colored/sweep_team.hpp"

namespace dc::colored {
namespace {

/// A layout of single-contact ranges; batch b's first lane is on body keys[b] (and a zero body).
Prepared with_keys(std::vector<Range> ranges, const std::vector<int>& keys) {
  Prepared p;
  p.ranges = std::move(ranges);
  p.body_entries = kStride * 1000;
  p.batches.resize(keys.size());
  for (size_t b = 0; b < keys.size(); ++b) {
    p.batches[b].la[0] = kStride * keys[b];
    p.batches[b].lb[0] = p.body_entries;
    p.batches[b].count = 1;
  }
  return p;
}

TEST(PgsColoredSweepTeam, RegionCutsGiveEachThreadTheSameBodiesInEveryColour) {
  // Colour 0 crowds the low bodies, colour 1 the high ones: an even split of each colour by
  // count would give thread 0 bodies 0–4 in colour 0 but 40–55 in colour 1.
  const std::vector<int> keys = {0, 1, 2, 3, 4, 5, 6, 7, 40, 41,  // colour 0: batches 0–9
                                 3, 40, 45, 50, 55, 60, 65, 70,   // colour 1: batches 10–17
                                 900, 901};                        // overflow (serial)
  const Prepared p = with_keys({{0, 10, false, false}, {10, 18, false, false}, {18, 20, true, false}}, keys);
  std::vector<int> scratch, cuts;
  region_cuts(p, 2, scratch, cuts);
  ASSERT_EQ(cuts.size(), 3u);  // threads − 1 per range
  int most0 = -1, least1 = 1 << 30;
  for (size_t k = 0; k < 2; ++k) {
    const Range& rg = p.ranges[k];
    ASSERT_GE(cuts[k], rg.begin);
    ASSERT_LE(cuts[k], rg.end);
    for (int b = rg.begin; b < rg.end; ++b) {
      const int key = keys[static_cast<size_t>(b)];
      if (b < cuts[k])
        most0 = std::max(most0, key);
      else
        least1 = std::min(least1, key);
    }
  }
  EXPECT_LT(most0, least1);  // one region per thread across the colours
  EXPECT_GT(cuts[0], 10 - cuts[0]);  // colour 0: mostly thread 0's
  EXPECT_LT(cuts[1] - 10, 18 - cuts[1]);  // colour 1: mostly thread 1's
  std::vector<int> one;
  region_cuts(p, 1, scratch, one);
  EXPECT_TRUE(one.empty());
}

TEST(PgsColoredSweepTeam, EveryBatchOncePerSweepOnTwoThreads) {
  // Ranges of many chunks and of one batch (an empty block), an overflow set.
  std::vector<int> keys;
  for (int b = 0; b < 300; ++b) keys.push_back(b % 150);
  const Prepared p = with_keys({{0, 170, false, false}, {170, 171, false, false}, {171, 290, false, false},
                                {290, 300, true, false}},
                               keys);
  for (const bool cut : {true, false}) {
    std::vector<int> scratch, cuts;
    if (cut) region_cuts(p, 2, scratch, cuts);
    SweepTeam team(p.ranges, 2, cuts);
    constexpr int kSweeps = 50;
    std::vector<std::atomic<int>> swept(p.batches.size());
    auto run = [&](int, int lo, int hi, Acc&) {
      for (int b = lo; b < hi; ++b) swept[static_cast<size_t>(b)].fetch_add(1);
    };
    std::thread helper([&] {
      int s = -1;
      const double* in = nullptr;
      double* out = nullptr;
      for (int last = -1; team.next(last, s, in, out); last = s) team.share(s, 1, run);
    });
    for (int s = 0; s < kSweeps; ++s) {
      team.start(s, nullptr, nullptr);
      team.share(s, 0, run);
      (void)team.finish(s);
      for (size_t b = 0; b < swept.size(); ++b) ASSERT_EQ(swept[b].load(), s + 1) << "batch " << b << ", sweep " << s;
    }
    team.stop();
    helper.join();
  }
}

TEST(PgsColoredSweepTeam, SmallColoursAreSweptByThreadZeroAloneInColourOrder) {
  // Large colours around runs of small ones (fewer than kSoloChunks chunks a thread), the last
  // one small. Thread 0 is slow in the small colours, so a helper that went on past one of them
  // before it was done, or that claimed one, shows in the order or in the sweeping thread.
  const int small = SweepTeam::kSoloChunks * SweepTeam::kChunk * 2 - 1;
  std::vector<Range> ranges;
  int at = 0;
  for (const int n : {120, small, 3, 1, 90, 2, 64, small}) {
    ranges.push_back({at, at + n, false, false});
    at += n;
  }
  std::vector<int> keys;
  for (int b = 0; b < at; ++b) keys.push_back((b * 7) % 200);
  const Prepared p = with_keys(ranges, keys);
  std::vector<int> range_of(static_cast<size_t>(at));
  for (size_t k = 0; k < ranges.size(); ++k)
    for (int b = ranges[k].begin; b < ranges[k].end; ++b) range_of[static_cast<size_t>(b)] = static_cast<int>(k);
  std::vector<int> scratch, cuts;
  region_cuts(p, 2, scratch, cuts);
  SweepTeam team(p.ranges, 2, cuts);
  std::vector<std::atomic<int>> swept(static_cast<size_t>(at)), by(static_cast<size_t>(at));
  std::vector<std::atomic<long>> first(ranges.size()), last(ranges.size());  // sequence numbers in a sweep
  std::atomic<long> seq{0};
  const auto runner = [&](int tid) {
    return [&, tid](int k, int lo, int hi, Acc&) {
      const bool is_small = ranges[static_cast<size_t>(k)].end - ranges[static_cast<size_t>(k)].begin <= small;
      if (is_small) std::this_thread::sleep_for(std::chrono::microseconds(200));
      for (int b = lo; b < hi; ++b) {
        const long t = seq.fetch_add(1);
        long f = first[static_cast<size_t>(k)].load();
        while (t < f && !first[static_cast<size_t>(k)].compare_exchange_weak(f, t)) {}
        long l = last[static_cast<size_t>(k)].load();
        while (t > l && !last[static_cast<size_t>(k)].compare_exchange_weak(l, t)) {}
        swept[static_cast<size_t>(b)].fetch_add(1);
        if (is_small) by[static_cast<size_t>(b)].fetch_or(1 << tid);
      }
    };
  };
  std::thread helper([&] {
    int s = -1;
    const double* in = nullptr;
    double* out = nullptr;
    for (int last_s = -1; team.next(last_s, s, in, out); last_s = s) team.share(s, 1, runner(1));
  });
  for (int s = 0; s < 20; ++s) {
    for (size_t k = 0; k < ranges.size(); ++k) {
      first[k] = std::numeric_limits<long>::max();
      last[k] = -1;
    }
    team.start(s, nullptr, nullptr);
    team.share(s, 0, runner(0));
    (void)team.finish(s);
    for (int b = 0; b < at; ++b) ASSERT_EQ(swept[static_cast<size_t>(b)].load(), s + 1) << "batch " << b << ", sweep " << s;
    for (size_t k = 1; k < ranges.size(); ++k)
      ASSERT_LT(last[k - 1].load(), first[k].load()) << "colour " << k << " began before colour " << k - 1 << " ended, sweep " << s;
  }
  team.stop();
  helper.join();
  for (int b = 0; b < at; ++b)
    if (ranges[static_cast<size_t>(range_of[static_cast<size_t>(b)])].end - ranges[static_cast<size_t>(range_of[static_cast<size_t>(b)])].begin <= small)
      EXPECT_EQ(by[static_cast<size_t>(b)].load(), 1) << "batch " << b << " of a small colour swept by a helper";
}

}  // namespace
}  // namespace dc::colored
