// The Trainer's epoch plan and sample stream (shuffle_stream.hpp): every sample exactly once
// per epoch, at most the buffer resident, the whole regime's Fisher–Yates order, and the
// Trainer reading each training sample once per epoch from its source.
#include <algorithm>
#include <cstring>
#include <numeric>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "dc/core/error.hpp"
#include "dc/learning/arch.hpp"
#include "dc/learning/feature_channels.hpp"
#include "dc/learning/shuffle_stream.hpp"
#include "dc/learning/trainer.hpp"

namespace dc {
namespace {

/// Sample i: every feature value i, every label value 2i + 1; counts the reads of each sample.
class CountingSource final : public SampleSource {
 public:
  CountingSource(std::size_t n, int sims) : reads_(n, 0), n_(n), sims_(sims) {}
  [[nodiscard]] std::size_t size() const override { return n_; }
  [[nodiscard]] int simulation(std::size_t i) const override { return static_cast<int>(i) * sims_ / static_cast<int>(n_); }
  [[nodiscard]] Shape feature_shape() const override { return {1, 2, 5, 5}; }
  [[nodiscard]] Shape label_shape() const override { return {1, 1, 5, 5}; }
  [[nodiscard]] int weight_channels() const override { return 0; }
  void read(std::span<const std::size_t> indices, Tensor& x, Tensor& y, Tensor&) const override {
    const int k = static_cast<int>(indices.size());
    x.resize(feature_shape().with_batch(k));
    y.resize(label_shape().with_batch(k));
    for (int j = 0; j < k; ++j) {
      const std::size_t i = indices[static_cast<std::size_t>(j)];
      ++reads_.at(i);
      std::fill(x.sample(j), x.sample(j) + feature_shape().sample_count(), static_cast<float>(i));
      std::fill(y.sample(j), y.sample(j) + label_shape().sample_count(), static_cast<float>(2 * i + 1));
    }
  }
  mutable std::vector<int> reads_;

 private:
  std::size_t n_;
  int sims_;
};

void expect_permutation(const std::vector<std::size_t>& order, std::size_t n) {
  std::vector<std::size_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::size_t> identity(n);
  std::iota(identity.begin(), identity.end(), std::size_t{0});
  EXPECT_EQ(sorted, identity);
}

TEST(ShuffleStream, PlanVisitsEverySampleOncePerEpochWithinTheBuffer) {
  Rng rng(4);
  for (const auto& [n, buffer, block] : std::vector<std::tuple<std::size_t, std::size_t, std::size_t>>{
           {100, 10, 3}, {101, 16, 16}, {57, 5, 16}, {64, 63, 1}, {1000, 37, 8}}) {
    const EpochPlan plan = plan_epoch(n, buffer, block, rng);
    SCOPED_TRACE(testing::Message() << "n " << n << " buffer " << buffer << " block " << block);
    expect_permutation(plan.order, n);
    ASSERT_EQ(plan.blocks_before.size(), n);
    // Replay the reads: the resident count never exceeds the buffer, and a sample is taken
    // only after its block was read.
    const std::size_t L = std::min(block, buffer);
    std::vector<bool> read(n, false);
    std::size_t resident = 0, blocks = 0;
    for (std::size_t k = 0; k < n; ++k) {
      for (; blocks < plan.blocks_before[k]; ++blocks)
        for (std::size_t p = plan.blocks[blocks] * L; p < std::min(n, (plan.blocks[blocks] + 1) * L); ++p, ++resident)
          read[p] = true;
      EXPECT_LE(resident, buffer);
      ASSERT_TRUE(read[plan.order[k]]) << "sample " << plan.order[k] << " taken before its block was read";
      --resident;
    }
    EXPECT_EQ(blocks, (n + L - 1) / L);
    // The order is shuffled, not the blocks one after the other.
    std::vector<std::size_t> identity(n);
    std::iota(identity.begin(), identity.end(), std::size_t{0});
    EXPECT_NE(plan.order, identity);
  }
}

TEST(ShuffleStream, ASplitThatFitsIsVisitedInTheFisherYatesOrderOfBefore) {
  // The order the Trainer used when every sample was in memory: the identity shuffled by
  // Fisher–Yates, n − 1 draws; small data sets therefore train bit-identically to before.
  Rng a(9), b(9);
  const EpochPlan plan = plan_epoch(50, 50, 4, a);
  std::vector<std::size_t> expected(50);
  std::iota(expected.begin(), expected.end(), std::size_t{0});
  for (std::size_t i = expected.size(); i > 1; --i) std::swap(expected[i - 1], expected[b.uniform_int(i)]);
  EXPECT_EQ(plan.order, expected);
  EXPECT_TRUE(plan.blocks_before.empty());
  EXPECT_EQ(a.save_state(), b.save_state());  // the same draws, so the dropout masks are equal too
  EXPECT_THROW((void)plan_epoch(5, 0, 1, a), InvalidArgument);
}

TEST(ShuffleStream, StreamHoldsAtMostTheBufferAndDeliversEverySampleOnce) {
  const CountingSource source(203, 4);
  std::vector<std::size_t> positions;
  for (std::size_t i = 0; i < source.size(); i += 2) positions.push_back(i);  // a split: every other sample
  const ChannelStats in = ChannelStats::identity(2), out = ChannelStats::identity(1);
  ShuffleStream stream(source, positions, in, out, 12, 5);
  ASSERT_TRUE(stream.buffered());
  Rng rng(1);
  Tensor x, y, w;
  for (int epoch = 0; epoch < 3; ++epoch) {
    stream.start_epoch(rng);
    std::multiset<std::size_t> seen;
    for (std::size_t first = 0; first < stream.size(); first += 7) {
      const int b = static_cast<int>(std::min<std::size_t>(7, stream.size() - first));
      stream.next_batch(b, 0, b, x, y, w);
      for (int k = 0; k < b; ++k) {
        const auto i = static_cast<std::size_t>(x.sample(k)[0]);
        EXPECT_EQ(y.sample(k)[3], static_cast<float>(2 * i + 1));  // features and labels stay paired
        seen.insert(i);
      }
      EXPECT_LE(stream.resident(), 12u);
    }
    EXPECT_EQ(seen, std::multiset<std::size_t>(positions.begin(), positions.end()));
    for (std::size_t i = 0; i < source.size(); ++i)  // each sample of the split read once per epoch, no other
      EXPECT_EQ(source.reads_[i], i % 2 == 0 ? epoch + 1 : 0) << "sample " << i;
    EXPECT_THROW(stream.next_batch(1, 0, 1, x, y, w), InvalidArgument);
  }
  EXPECT_LE(stream.peak_resident(), 12u);
  EXPECT_GT(stream.peak_resident(), 5u);
}

TEST(ShuffleStream, TrainerReadsEachTrainingSampleOncePerEpochThroughABoundedBuffer) {
  const CountingSource source(60, 5);
  Model model(ArchSpec::parse("[[layer]]\ntype = \"conv\"\nout = 1\n"), [] {
    ModelGrid g;
    g.image = FeatureImageDef::for_box(2.0, 2.0);
    const auto all = residual_feature_channels();
    g.image.channels.assign(all.begin(), all.begin() + 2);
    g.label_channels.clear();
    return g;
  }(), 2);
  TrainDef def;
  def.epochs = 3;
  def.batch_size = 8;
  def.shuffle_buffer = 10;  // 48 training samples
  def.learning_rate = 1e-4;
  const TrainResult r = Trainer(def).train(model, source, {}, nullptr);
  ASSERT_EQ(r.validation_simulations.size(), 1u);
  ASSERT_EQ(r.history.size(), 3u);
  for (std::size_t i = 0; i < source.size(); ++i) {
    const bool validation = source.simulation(i) == r.validation_simulations[0];
    // Training samples: once for the standardisation, once per epoch; validation: once per epoch.
    EXPECT_EQ(source.reads_[i], validation ? 3 : 4) << "sample " << i;
  }
}

}  // namespace
}  // namespace dc
