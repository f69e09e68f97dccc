// The epoch plan and the bounded-memory sample stream of the Trainer (shuffle_stream.hpp).
#include "dc/learning/shuffle_stream.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <string>

#include "dc/core/error.hpp"

namespace dc {

namespace {

/// The identity on 0 … n − 1 shuffled by Fisher–Yates from rng (n − 1 draws): the order of a
/// split held in memory.
std::vector<std::size_t> fisher_yates(std::size_t n, Rng& rng) {
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  for (std::size_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng.uniform_int(i)]);
  return order;
}

std::size_t block_count(std::size_t n, std::size_t block) { return (n + block - 1) / block; }

void copy_sample(const Tensor& src, std::size_t i, Tensor& dst, int k) {
  const std::size_t len = src.shape().sample_count();
  std::memcpy(dst.sample(k), src.sample(static_cast<int>(i)), sizeof(float) * len);
}

}  // namespace

EpochPlan plan_epoch(std::size_t n, std::size_t buffer, std::size_t block, Rng& rng) {
  if (buffer == 0 || block == 0) throw InvalidArgument("plan_epoch: the buffer and the read block must be >= 1 sample");
  EpochPlan plan;
  if (n <= buffer) {
    plan.order = fisher_yates(n, rng);
    return plan;
  }
  block = std::min(block, buffer);
  plan.blocks = fisher_yates(block_count(n, block), rng);
  plan.order.reserve(n);
  plan.blocks_before.reserve(n);
  std::vector<std::size_t> resident;  // positions in the buffer
  resident.reserve(buffer);
  std::size_t next_block = 0;
  for (std::size_t k = 0; k < n; ++k) {
    // Read blocks while a whole one fits: the buffer never holds more than `buffer` samples.
    while (next_block < plan.blocks.size()) {
      const std::size_t first = plan.blocks[next_block] * block, last = std::min(n, first + block);
      if (resident.size() + (last - first) > buffer) break;
      for (std::size_t p = first; p < last; ++p) resident.push_back(p);
      ++next_block;
    }
    const std::size_t j = rng.uniform_int(resident.size());
    plan.order.push_back(resident[j]);
    plan.blocks_before.push_back(next_block);
    resident[j] = resident.back();
    resident.pop_back();
  }
  return plan;
}

ShuffleStream::ShuffleStream(const SampleSource& source, std::vector<std::size_t> positions, const ChannelStats& in,
                             const ChannelStats& out, std::size_t buffer, std::size_t block)
    : source_(source), positions_(std::move(positions)), in_(in), out_(out), buffer_(buffer),
      block_(std::min(block, buffer)), buffered_(positions_.size() > buffer), wc_(source.weight_channels()) {
  if (buffer == 0 || block == 0) throw InvalidArgument("ShuffleStream: the buffer and the read block must be >= 1 sample");
  const std::size_t slots = std::min(buffer_, positions_.size());
  const Shape ys = source_.label_shape();
  x_.resize(source_.feature_shape().with_batch(static_cast<int>(slots)));
  y_.resize(ys.with_batch(static_cast<int>(slots)));
  if (wc_ > 0) w_.resize({static_cast<int>(slots), wc_, ys.h, ys.w});
  if (buffered_) {
    slot_of_.assign(positions_.size(), 0);
    return;
  }
  // The whole split, in blocks of consecutive positions (slot = position).
  std::vector<std::size_t> which;
  for (std::size_t first = 0; first < positions_.size(); first += block_) {
    const std::size_t last = std::min(positions_.size(), first + block_);
    which.resize(last - first);
    std::iota(which.begin(), which.end(), first);
    read_positions(which, which);
  }
  resident_ = peak_ = positions_.size();
}

void ShuffleStream::read_positions(std::span<const std::size_t> which, std::span<const std::size_t> slots) {
  std::vector<std::size_t> indices(which.size());
  for (std::size_t j = 0; j < which.size(); ++j) indices[j] = positions_[which[j]];
  source_.read(indices, bx_, by_, bw_);
  in_.apply(bx_);
  out_.apply(by_);
  for (std::size_t j = 0; j < which.size(); ++j) {
    copy_sample(bx_, j, x_, static_cast<int>(slots[j]));
    copy_sample(by_, j, y_, static_cast<int>(slots[j]));
    if (wc_ > 0) copy_sample(bw_, j, w_, static_cast<int>(slots[j]));
  }
}

void ShuffleStream::read_block(std::size_t block) {
  const std::size_t first = block * block_, last = std::min(positions_.size(), first + block_);
  std::vector<std::size_t> which(last - first), slots(last - first);
  std::iota(which.begin(), which.end(), first);
  for (std::size_t j = 0; j < which.size(); ++j) {
    if (free_.empty()) throw InvalidArgument("ShuffleStream: buffer overrun (plan and stream disagree)");
    slots[j] = free_.back();
    free_.pop_back();
    slot_of_[which[j]] = slots[j];
  }
  read_positions(which, slots);
  resident_ += which.size();
  peak_ = std::max(peak_, resident_);
}

void ShuffleStream::start_epoch(Rng& rng) {
  plan_ = plan_epoch(positions_.size(), buffer_, block_, rng);
  next_ = 0;
  blocks_read_ = 0;
  if (!buffered_) return;
  resident_ = 0;
  free_.resize(std::min(buffer_, positions_.size()));
  // Lowest slots first, so a short epoch touches few pages.
  for (std::size_t s = 0; s < free_.size(); ++s) free_[s] = free_.size() - 1 - s;
}

void ShuffleStream::next_batch(int b, int lo, int count, Tensor& x, Tensor& y, Tensor& w) {
  if (b < 0 || next_ + static_cast<std::size_t>(b) > plan_.order.size() || lo < 0 || count < 0 || lo + count > b)
    throw InvalidArgument("ShuffleStream::next_batch: " + std::to_string(b) + " samples past the epoch's " +
                          std::to_string(plan_.order.size() - next_) + " left");
  x.resize(x_.shape().with_batch(count));
  y.resize(y_.shape().with_batch(count));
  if (wc_ > 0) w.resize(w_.shape().with_batch(count));
  for (int k = 0; k < b; ++k, ++next_) {
    const std::size_t p = plan_.order[next_];
    std::size_t slot = p;
    if (buffered_) {
      while (blocks_read_ < plan_.blocks_before[next_]) read_block(plan_.blocks[blocks_read_++]);
      slot = slot_of_[p];
    }
    if (k >= lo && k < lo + count) {
      copy_sample(x_, slot, x, k - lo);
      copy_sample(y_, slot, y, k - lo);
      if (wc_ > 0) copy_sample(w_, slot, w, k - lo);
    }
    if (buffered_) {
      free_.push_back(slot);
      --resident_;
    }
  }
}

}  // namespace dc
