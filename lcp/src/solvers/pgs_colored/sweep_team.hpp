#pragma once
// The threads of one pgs-colored solve's sweeps (pgs_colored.cpp, sweeps_threaded). Thread 0
// runs the sweep driver and publishes each sweep (start); every thread then takes the batches of
// colour 0, 1, …, overflow in chunks: first from its own block of the colour (region_cuts: the
// batches on the thread's region of the bodies, the same region in every colour, so the Δu it
// writes stay in its core's cache; an odd block from its back), then from the other end of the
// other threads' blocks. A thief thus takes the chunks its owner would reach last (the two meet
// once per block, next to the thief's own region), the same ones sweep after sweep while an
// imbalance persists. A small colour is thread 0's alone (kSoloChunks). A colour starts once
// every batch of the previous colour is done. No thread waits for
// another to arrive: a thread that is descheduled (another program on its core) has its share
// done by the others, and waits (spin, yield, sleep: dc/core/wake_word.hpp) happen only for a
// chunk in progress or for the next sweep. Which thread runs a batch does not change the result
// (a colour's batches touch disjoint bodies; θ and the flag combine as max and or).
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "dc/core/wake_word.hpp"

namespace dc::colored {

class SweepTeam {
 public:
  /// Batches per chunk: kChunk, or more for a block of over kMostChunks chunks (the cursor's
  /// 16-bit counts); the owner claims several at once (claim), the serial overflow set is one.
  static constexpr int kChunk = 8;
  static constexpr int kMostChunks = 1024;
  /// A colour of fewer than kSoloChunks · kChunk batches a thread is swept by thread 0 alone, in
  /// one claim and never stolen: split, each thread would get a chunk or two, less work than the
  /// colour's barrier (its done counts read across the cores, its Δu lines moved); alone, thread
  /// 0 runs a tail of such colours back to back while the others go on to the next colour they
  /// share (waiting for the one before it: thread 0 sweeps the colours in order). A colour's
  /// batches touch disjoint bodies, so which thread sweeps them changes no bit.
  static constexpr int kSoloChunks = 2;

  /// `cuts` (region_cuts: threads − 1 per range) bound the threads' blocks of each range that
  /// is not serial; empty: each range split evenly by batch count.
  SweepTeam(const std::vector<Range>& ranges, int threads, const std::vector<int>& cuts = {}) {
    reset(ranges, threads, cuts);
  }
  /// An empty team, for reset() (a solver keeps one team from solve to solve).
  SweepTeam() = default;

  /// The team of a new solve (as the constructor makes it) in the storage of the last one: it
  /// allocates only when ranges × threads exceeds every earlier solve's. Not while a sweep runs.
  void reset(const std::vector<Range>& ranges, int threads, const std::vector<int>& cuts = {}) {
    nt_ = std::max(1, threads);
    nr_ = static_cast<int>(ranges.size());
    const size_t blocks = static_cast<size_t>(nr_ * nt_);
    blocks_.resize(blocks);
    total_.resize(static_cast<size_t>(nr_));
    slots_.assign(static_cast<size_t>(nt_), Slot{});
    if (blocks > counters_) {  // (atomics cannot move: a larger array, value-initialised)
      cursors_ = std::make_unique<Cursor[]>(blocks);
      done_ = std::make_unique<Done[]>(blocks);
      counters_ = blocks;
    } else {
      for (size_t i = 0; i < blocks; ++i) {
        cursors_[i].next.store(0, std::memory_order_relaxed);
        done_[i].count.store(0, std::memory_order_relaxed);
      }
    }
    seq_.store(-1);
    in_.store(nullptr);
    out_.store(nullptr);
    stopped_.store(false);
    const bool cut = cuts.size() == static_cast<size_t>(nr_ * (nt_ - 1));
    for (int k = 0; k < nr_; ++k) {
      const Range& rg = ranges[static_cast<size_t>(k)];
      const long n = rg.end - rg.begin;
      auto bound = [&](int b) {  // first batch of block b (b = 0 … nt_)
        if (b == 0 || b == nt_) return b == 0 ? rg.begin : rg.end;
        return cut ? cuts[static_cast<size_t>(k * (nt_ - 1) + b - 1)] : rg.begin + static_cast<int>(n * b / nt_);
      };
      const bool solo = !rg.serial && nt_ > 1 && n < static_cast<long>(kSoloChunks) * kChunk * nt_;
      for (int b = 0; b < nt_; ++b) {
        Block& bl = blocks_[static_cast<size_t>(k * nt_ + b)];
        const bool whole = rg.serial || solo;  // block 0 holds the range
        bl.lo = whole ? (b == 0 ? rg.begin : rg.end) : bound(b);
        bl.hi = whole ? rg.end : bound(b + 1);
        bl.chunk = whole ? std::max(1, bl.hi - bl.lo) : std::max(kChunk, (bl.hi - bl.lo + kMostChunks - 1) / kMostChunks);
        bl.chunks = bl.lo < bl.hi ? (bl.hi - bl.lo + bl.chunk - 1) / bl.chunk : 0;
        bl.solo = solo;
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
      if (tid != 0 && blocks_[static_cast<size_t>(k * nt_)].solo) continue;  // thread 0's alone
      if (k > 0) wait_done(k - 1, s);
      if (stopped_.load()) return;
      int swept = 0;  // batches of range k swept by this thread (published once: add_done)
      for (int j = 0; j < nt_; ++j) {
        const int b = (tid + j) % nt_;
        int lo = 0, hi = 0;
        while (claim(k, b, s, b != tid, lo, hi)) {
          if (mine.sweep != s) mine = Slot{s, Acc{}};
          run(k, lo, hi, mine.acc);
          swept += hi - lo;
        }
      }
      if (swept > 0) add_done(k, tid, swept, s);
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
    int lo = 0, hi = 0, chunk = kChunk, chunks = 0;  // chunks: ⌈(hi − lo) / chunk⌉ (at most kMostChunks)
    bool solo = false;  // of a colour thread 0 sweeps alone (kSoloChunks): no thief claims it
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
    if (bl.chunks == 0 || (thief && bl.solo)) return false;
    std::atomic<std::uint64_t>& cur = cursors_[i].next;
    const std::uint64_t tag = static_cast<std::uint64_t>(s + 1) << 32;
    std::uint64_t c = cur.load();
    for (;;) {
      const std::uint64_t ctag = c & ~std::uint64_t{0xffffffff};
      if (ctag > tag) return false;
      const int front = ctag < tag ? 0 : static_cast<int>((c >> 16) & 0xffff);
      const int back = ctag < tag ? 0 : static_cast<int>(c & 0xffff);
      if (front + back >= bl.chunks) return false;
      // The owner takes half of what is left (at least a chunk), a thief one chunk: few claims
      // (each a locked operation on a line the other cores may hold) while a late thread can
      // still take over.
      const int take = thief ? 1 : std::max(1, (bl.chunks - front - back) / 2);
      const int idx = thief ? bl.chunks - 1 - back : front;  // first chunk taken
      const std::uint64_t next = tag | static_cast<std::uint64_t>(front + (thief ? 0 : take)) << 16 |
                                 static_cast<std::uint64_t>(back + (thief ? 1 : 0));
      if (cur.compare_exchange_weak(c, next)) {
        // Odd blocks run from the back: neighbouring blocks 2i and 2i + 1 then meet, and are
        // stolen from, at their common bound (bodies both threads' regions border on).
        const int at = b % 2 ? bl.chunks - idx - take : idx;
        lo = bl.lo + at * bl.chunk;
        hi = std::min(bl.hi, lo + take * bl.chunk);
        return true;
      }
    }
  }

  void add_done(int k, int tid, int n, int s) {
    std::atomic<std::int64_t>& c = done_[static_cast<size_t>(k * nt_ + tid)].count;
    c.store(c.load(std::memory_order_relaxed) + n);
    // complete() reads every thread's count, a line the other cores write: only for a sleeper.
    if (wake_.sleeping() && complete(k, s)) wake_.notify();
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

  int nt_ = 1, nr_ = 0;
  std::vector<Block> blocks_;
  std::unique_ptr<Cursor[]> cursors_;  // per range and thread (blocks_'s order)
  std::unique_ptr<Done[]> done_;       // per range and thread
  size_t counters_ = 0;                // entries of cursors_ and done_
  std::vector<std::int64_t> total_;
  std::vector<Slot> slots_;
  std::atomic<int> seq_{-1};
  std::atomic<const double*> in_{nullptr};
  std::atomic<double*> out_{nullptr};
  std::atomic<bool> stopped_{false};
  WakeWord wake_;
};

/// The key of a batch: the Δu offset of its first lane's lower dynamic body (kStride·slot; with
/// the locality order the contacts of a colour are in the order of that slot, so the keys grow
/// along a range: setup/body_numbering.hpp).
template <class B>
int batch_key(const B& batch) {
  return std::min(batch.la[0], batch.lb[0]);
}

/// batch_key of pair batch i (pairs) or of single batch i in the layout the sweeps read.
inline int single_or_pair_key(const Prepared& prep, bool pairs, int i) {
  const auto k = static_cast<size_t>(i);
  return pairs ? batch_key(prep.pairs[k]) : prep.compact_on ? batch_key(prep.compact[k]) : batch_key(prep.batches[k]);
}

/// Block bounds for SweepTeam that give each thread one region of the bodies in every colour:
/// key cuts K_1 ≤ … ≤ K_{threads−1} at the quantiles of the batches' keys (a pair batch
/// counted twice: it holds two contacts per lane), and in each range that is not serial the
/// block of thread t starting after the range's batches with keys below K_t. A thread then
/// reads and writes the same bodies' Δu from colour to colour (its own cache), where an even
/// split of each range by count would put the split at a different body in each colour (the
/// colours are not spread evenly over the pile) and move Δu between the cores at every colour.
/// `keys` is scratch (the keys, then the key cuts); `cuts` gets threads − 1 bounds per range.
inline void region_cuts(const Prepared& prep, int threads, std::vector<int>& keys, std::vector<int>& cuts) {
  const int nt = std::max(1, threads);
  cuts.clear();
  if (nt == 1) return;
  keys.clear();
  for (const Range& rg : prep.ranges)
    for (int i = rg.begin; i < rg.end && !rg.serial; ++i)
      for (int c = 0; c < (rg.pairs ? 2 : 1); ++c)
        keys.push_back(single_or_pair_key(prep, rg.pairs, i));
  // The key cuts K_t, appended to `keys` after its nk keys (no vector of their own: a solve
  // allocates nothing here once the scratch has grown to the problem).
  const size_t nk = keys.size();
  for (int t = 1; t < nt; ++t) {
    if (nk == 0) {
      keys.push_back(0);
      continue;
    }
    const auto q = keys.begin() + static_cast<long>(nk * static_cast<size_t>(t) / static_cast<size_t>(nt));
    std::nth_element(keys.begin(), q, keys.begin() + static_cast<long>(nk));
    keys.push_back(*q);
  }
  const int* const at = keys.data() + nk;
  for (const Range& rg : prep.ranges)
    for (int t = 1; t < nt; ++t) {
      int below = 0;
      for (int i = rg.begin; i < rg.end && !rg.serial; ++i)
        below += single_or_pair_key(prep, rg.pairs, i) < at[t - 1];
      cuts.push_back(rg.begin + below);
    }
}

}  // namespace dc::colored
