#pragma once
// The threads of one pgs-colored solve's sweeps (pgs_colored.cpp, sweeps_threaded). Thread 0
// runs the sweep driver and publishes each sweep (start); every thread then takes the batches of
// colour 0, 1, …, overflow in chunks: first from the front of its own block of the colour (the
// colour's batches split evenly by thread, so a thread keeps its region of the pile), then from
// the far end of the other threads' blocks. A thief thus takes the chunks its owner would reach
// last (the two meet once per block), the same ones sweep after sweep while an imbalance
// persists. A colour starts once every batch of the previous colour is done. No thread waits for
// another to arrive: a thread that is descheduled (another program on its core) has its share
// done by the others, and waits (spin, yield, sleep: dc/core/wake_word.hpp) happen only for a
// chunk in progress or for the next sweep. Which thread runs a batch does not change the result
// (a colour's batches touch disjoint bodies; θ and the flag combine as max and or).
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <vector>

#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "dc/core/wake_word.hpp"

namespace dc::colored {

class SweepTeam {
 public:
  /// Batches per claim: an eighth of the block, at least kChunk (the serial overflow set is one
  /// claim).
  static constexpr int kChunk = 8;

  SweepTeam(const std::vector<Range>& ranges, int threads)
      : nt_(std::max(1, threads)), nr_(static_cast<int>(ranges.size())), blocks_(static_cast<size_t>(nr_ * nt_)),
        cursors_(blocks_.size()), done_(blocks_.size()), total_(static_cast<size_t>(nr_)),
        slots_(static_cast<size_t>(nt_)) {
    for (int k = 0; k < nr_; ++k) {
      const Range& rg = ranges[static_cast<size_t>(k)];
      const long n = rg.end - rg.begin;
      for (int b = 0; b < nt_; ++b) {
        Block& bl = blocks_[static_cast<size_t>(k * nt_ + b)];
        bl.lo = rg.serial ? (b == 0 ? rg.begin : rg.end) : rg.begin + static_cast<int>(n * b / nt_);
        bl.hi = rg.serial ? rg.end : rg.begin + static_cast<int>(n * (b + 1) / nt_);
        bl.chunk = rg.serial ? std::max(1, bl.hi - bl.lo) : std::max(kChunk, (bl.hi - bl.lo) / 8);
        bl.chunks = bl.lo < bl.hi ? (bl.hi - bl.lo + bl.chunk - 1) / bl.chunk : 0;
      }
      total_[static_cast<size_t>(k)] = n;
    }
  }

  /// Thread 0: sweep s (0, 1, …) reads `in` and writes `out`; wakes the others.
  void start(int s, const double* in, double* out) {
    in_.store(in);
    out_.store(out);
    seq_.store(s);
    wake_.notify();
  }

  /// The other threads: waits for a sweep after `last`; false once stop() was called.
  bool next(int last, int& s, const double*& in, double*& out) {
    wake_.wait([&] { return seq_.load() > last || stopped_.load(); });
    if (stopped_.load()) return false;
    s = seq_.load();
    in = in_.load();
    out = out_.load();
    return true;
  }

  /// Every thread: its part of sweep s. run(k, lo, hi, acc) sweeps batches [lo, hi) of range k
  /// into acc. A thread whose sweep is over (a later one started) claims nothing.
  template <class Run>
  void share(int s, int tid, Run&& run) {
    Slot& mine = slots_[static_cast<size_t>(tid)];
    for (int k = 0; k < nr_; ++k) {
      if (k > 0) wait_done(k - 1, s);
      if (stopped_.load()) return;
      for (int j = 0; j < nt_; ++j) {
        const int b = (tid + j) % nt_;
        int lo = 0, hi = 0;
        while (claim(k, b, s, b != tid, lo, hi)) {
          if (mine.sweep != s) mine = Slot{s, Acc{}};
          run(k, lo, hi, mine.acc);
          add_done(k, tid, hi - lo, s);
        }
      }
    }
  }

  /// Thread 0, after its share: waits until every batch of sweep s is done; θ and the flag of
  /// the sweep, combined in thread order.
  Acc finish(int s) {
    for (int k = 0; k < nr_; ++k) wait_done(k, s);
    Acc acc;
    for (const Slot& t : slots_) {
      if (t.sweep != s) continue;
      acc.theta = max_of(acc.theta, t.acc.theta);
      acc.bad = acc.bad || t.acc.bad;
    }
    return acc;
  }

  /// Thread 0: no more sweeps; the others return from next().
  void stop() {
    stopped_.store(true);
    wake_.notify();
  }

 private:
  struct Block {
    int lo = 0, hi = 0, chunk = kChunk, chunks = 0;  // chunks: ⌈(hi − lo) / chunk⌉ (at most 9)
  };
  /// A block's claimed chunks: sweep + 1 in the high half, the number taken from the front in
  /// bits 16–31 and from the back in bits 0–15 (a claim of an earlier sweep finds a later tag
  /// and takes nothing; an earlier tag means the block is untouched this sweep).
  struct alignas(64) Cursor {
    std::atomic<std::uint64_t> next{0};
  };
  /// Batches of a range done by one thread over all sweeps so far (written by that thread only;
  /// sweep s of range k is complete when the threads' counts sum to (s + 1)·total_[k]).
  struct alignas(64) Done {
    std::atomic<std::int64_t> count{0};
  };
  /// A thread's θ and flag of sweep `sweep` (written only by that thread).
  struct alignas(64) Slot {
    int sweep = -1;
    Acc acc;
  };

  /// The next chunk of block b of range k in sweep s: the front one for its owner, the back
  /// one for a thief; false when none is left.
  bool claim(int k, int b, int s, bool thief, int& lo, int& hi) {
    const size_t i = static_cast<size_t>(k * nt_ + b);
    const Block& bl = blocks_[i];
    if (bl.chunks == 0) return false;
    std::atomic<std::uint64_t>& cur = cursors_[i].next;
    const std::uint64_t tag = static_cast<std::uint64_t>(s + 1) << 32;
    std::uint64_t c = cur.load();
    for (;;) {
      const std::uint64_t ctag = c & ~std::uint64_t{0xffffffff};
      if (ctag > tag) return false;
      const int front = ctag < tag ? 0 : static_cast<int>((c >> 16) & 0xffff);
      const int back = ctag < tag ? 0 : static_cast<int>(c & 0xffff);
      if (front + back >= bl.chunks) return false;
      const int idx = thief ? bl.chunks - 1 - back : front;
      const std::uint64_t next = tag | static_cast<std::uint64_t>(front + (thief ? 0 : 1)) << 16 |
                                 static_cast<std::uint64_t>(back + (thief ? 1 : 0));
      if (cur.compare_exchange_weak(c, next)) {
        lo = bl.lo + idx * bl.chunk;
        hi = std::min(bl.hi, lo + bl.chunk);
        return true;
      }
    }
  }

  void add_done(int k, int tid, int n, int s) {
    std::atomic<std::int64_t>& c = done_[static_cast<size_t>(k * nt_ + tid)].count;
    c.store(c.load(std::memory_order_relaxed) + n);
    if (complete(k, s)) wake_.notify();
  }

  /// Every batch of range k is done in sweep s (each count read once; they only grow).
  bool complete(int k, int s) const {
    std::int64_t sum = 0;
    for (int t = 0; t < nt_; ++t) sum += done_[static_cast<size_t>(k * nt_ + t)].count.load();
    return sum >= (s + 1) * total_[static_cast<size_t>(k)];
  }

  void wait_done(int k, int s) {
    wake_.wait([&] { return complete(k, s) || stopped_.load(); });
  }

  int nt_, nr_;
  std::vector<Block> blocks_;
  std::vector<Cursor> cursors_;
  std::vector<Done> done_;  // per range and thread
  std::vector<std::int64_t> total_;
  std::vector<Slot> slots_;
  std::atomic<int> seq_{-1};
  std::atomic<const double*> in_{nullptr};
  std::atomic<double*> out_{nullptr};
  std::atomic<bool> stopped_{false};
  WakeWord wake_;
};

}  // namespace dc::colored
