#pragma once
// The training split as a stream of shuffled, standardised samples with bounded memory
// (docs/learning.md "Sample order and memory", docs/robustness.md "Memory of train").
// n ≤ B (buffer bound, samples): the split is read once and kept; each epoch is a
// Fisher–Yates permutation of all n (n − 1 draws). n > B: read blocks of L consecutive samples
// in a Fisher–Yates block order, each next sample a uniform draw among the ≤ B resident ones
// (the tf.data shuffle buffer fed by shuffled blocks). Every sample is visited exactly once per
// epoch. The epoch's whole plan is drawn from the run's stream when the epoch starts, ahead of
// any dropout mask: a function of (n, B, L) and the stream only, the same on every process of
// a data-parallel group, and a resumed run continues it exactly.
#include <cstddef>
#include <vector>

#include "dc/core/rng.hpp"
#include "dc/learning/channel_stats.hpp"
#include "dc/learning/sample_source.hpp"

namespace dc {

/// The visiting order of one epoch over positions 0 … n − 1 of a split, and its reads.
struct EpochPlan {
  std::vector<std::size_t> order;         ///< every position exactly once
  /// Buffered plans: blocks (of `blocks`, in that order) read before order[k] is taken;
  /// empty for a whole plan (everything is resident).
  std::vector<std::size_t> blocks_before;
  std::vector<std::size_t> blocks;        ///< block ids in reading order (buffered plans)
};

/// The epoch plan for n positions, buffer bound `buffer` ≥ 1 and read block `block` ≥ 1
/// samples (used as min(block, buffer)); draws from rng as the file comment says.
/// InvalidArgument for a zero buffer or block.
EpochPlan plan_epoch(std::size_t n, std::size_t buffer, std::size_t block, Rng& rng);

/// Streams the samples `positions` (indices into `source`, in data order) of a split: the
/// n ≤ B regime keeps them all, the buffered one at most B plus one read block in transit.
/// Values are standardised with the given statistics on read.
class ShuffleStream {
 public:
  /// The source and statistics must outlive the stream. Reads the whole split now when it
  /// fits the buffer.
  ShuffleStream(const SampleSource& source, std::vector<std::size_t> positions, const ChannelStats& in,
                const ChannelStats& out, std::size_t buffer, std::size_t block);

  [[nodiscard]] std::size_t size() const { return positions_.size(); }
  [[nodiscard]] bool buffered() const { return buffered_; }
  /// Draws the epoch's plan from rng and rewinds to its first sample.
  void start_epoch(Rng& rng);
  /// Takes the next b samples of the epoch and copies those with batch offsets
  /// [lo, lo + count) into x, y and (weighted sources) w. InvalidArgument past the end.
  void next_batch(int b, int lo, int count, Tensor& x, Tensor& y, Tensor& w);

  /// Samples held now and at most since construction (the bound the tests check).
  [[nodiscard]] std::size_t resident() const { return resident_; }
  [[nodiscard]] std::size_t peak_resident() const { return peak_; }

 private:
  void read_block(std::size_t block);
  void read_positions(std::span<const std::size_t> which, std::span<const std::size_t> slots);

  const SampleSource& source_;
  std::vector<std::size_t> positions_;
  const ChannelStats& in_;
  const ChannelStats& out_;
  std::size_t buffer_, block_;
  bool buffered_;
  int wc_;
  Tensor x_, y_, w_;                 // resident samples, one slot each
  Tensor bx_, by_, bw_;              // one read block in transit
  std::vector<std::size_t> slot_of_; // position → slot (buffered)
  std::vector<std::size_t> free_;    // free slots (buffered)
  EpochPlan plan_;
  std::size_t next_ = 0, blocks_read_ = 0, resident_ = 0, peak_ = 0;
};

}  // namespace dc
