// Data-parallel training (data_parallel.hpp): K "processes" are K threads whose group sums
// through shared memory in a fixed order. Every process ends with the same weights, and the
// weights and losses match the one-process run to rounding (the masks of the dropout
// layers and the random stream are the one-process ones; only the gradient sum is
// regrouped), also when a batch has fewer samples than processes.
#include <gtest/gtest.h>

#include <barrier>
#include <cmath>
#include <cstring>
#include <thread>

#include "dc/core/rng.hpp"
#include "dc/learning/arch.hpp"
#include "dc/learning/trainer.hpp"
#include "grad_check.hpp"

namespace dc {
namespace {

/// K threads of one test: sum() waits for all, then every thread adds the K buffers in
/// rank order (the same bits everywhere).
class ThreadGroup {
 public:
  explicit ThreadGroup(int k) : k_(k), slots_(static_cast<std::size_t>(k)), sync_(k) {}
  class Member final : public DataParallelGroup {
   public:
    Member(ThreadGroup& g, int r) : g_(g), r_(r) {}
    [[nodiscard]] int rank() const override { return r_; }
    [[nodiscard]] int size() const override { return g_.k_; }
    void sum(std::span<double> v) const override {
      g_.slots_[static_cast<std::size_t>(r_)].assign(v.begin(), v.end());
      g_.sync_.arrive_and_wait();
      for (std::size_t i = 0; i < v.size(); ++i) {
        double s = 0.0;
        for (const auto& slot : g_.slots_) s += slot[i];
        v[i] = s;
      }
      g_.sync_.arrive_and_wait();
    }

   private:
    ThreadGroup& g_;
    int r_;
  };

 private:
  int k_;
  std::vector<std::vector<double>> slots_;
  std::barrier<> sync_;
};

std::vector<TrainingSample> make_data(int n, int size, bool weighted) {
  Rng rng(17);
  std::vector<TrainingSample> data;
  for (int k = 0; k < n; ++k) {
    TrainingSample s;
    s.features = Tensor(1, 2, size, size);
    test::fill_gaussian(s.features, rng);
    s.labels = Tensor(1, 2, size, size);
    for (std::size_t i = 0; i < s.labels.size(); ++i)
      s.labels[i] = 1.0f + s.features[i] * s.features[(i + 1) % s.features.size()];
    if (weighted) {
      s.weights = Tensor(1, 1, size, size);
      for (std::size_t i = 0; i < s.weights.size(); ++i) s.weights[i] = static_cast<float>(rng.uniform(0.5, 2.0));
    }
    s.simulation = k % 5;
    data.push_back(std::move(s));
  }
  return data;
}

ModelGrid grid_for(int size) {
  ModelGrid g;
  g.image = FeatureImageDef::for_box(0.5 * (size - 1), 0.5 * (size - 1));
  const auto all = residual_feature_channels();
  g.image.channels.assign(all.begin(), all.begin() + 2);
  return g;
}

struct TrainRun {
  std::vector<float> weights;
  TrainResult result;
};

TrainRun train(const std::vector<TrainingSample>& data, const TrainDef& def, const DataParallelGroup* group) {
  Model model(default_arch(2, 0.2), grid_for(13), 2);
  Trainer t(def);
  t.set_data_parallel(group);
  TrainRun r;
  r.result = t.train(model, data);
  for (const ParamRef& p : model.network().parameters())
    r.weights.insert(r.weights.end(), p.value->data(), p.value->data() + p.value->size());
  return r;
}

std::vector<TrainRun> train_parallel(int k, const std::vector<TrainingSample>& data, const TrainDef& def) {
  ThreadGroup group(k);
  std::vector<TrainRun> runs(static_cast<std::size_t>(k));
  std::vector<std::thread> threads;
  for (int r = 0; r < k; ++r)
    threads.emplace_back([&, r] {
      const ThreadGroup::Member m(group, r);
      runs[static_cast<std::size_t>(r)] = train(data, def, &m);
    });
  for (auto& t : threads) t.join();
  return runs;
}

double max_relative_difference(const std::vector<float>& a, const std::vector<float>& b) {
  double diff = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, static_cast<double>(std::abs(a[i] - b[i])));
    scale = std::max(scale, static_cast<double>(std::abs(a[i])));
  }
  return diff / scale;
}

void expect_like_one_process(int k, int batch, bool weighted, std::size_t shuffle_buffer = TrainDef{}.shuffle_buffer) {
  const auto data = make_data(11, 13, weighted);
  TrainDef def;
  def.epochs = 2;
  def.batch_size = batch;
  def.seed = 5;
  def.shuffle_buffer = shuffle_buffer;
  const TrainRun one = train(data, def, nullptr);
  const std::vector<TrainRun> many = train_parallel(k, data, def);
  for (int r = 1; r < k; ++r)  // every process holds the same weights
    EXPECT_EQ(std::memcmp(many[0].weights.data(), many[static_cast<std::size_t>(r)].weights.data(),
                          sizeof(float) * one.weights.size()), 0) << "rank " << r;
  ASSERT_EQ(many[0].weights.size(), one.weights.size());
  EXPECT_LT(max_relative_difference(many[0].weights, one.weights), 1e-4);
  ASSERT_EQ(many[0].result.history.size(), one.result.history.size());
  for (std::size_t e = 0; e < one.result.history.size(); ++e) {
    EXPECT_NEAR(many[0].result.history[e].train_loss, one.result.history[e].train_loss,
                1e-4 * one.result.history[e].train_loss);
    EXPECT_NEAR(many[0].result.history[e].validation_loss, one.result.history[e].validation_loss,
                1e-4 * one.result.history[e].validation_loss);
  }
  EXPECT_EQ(many[0].result.validation_simulations, one.result.validation_simulations);
}

TEST(DataParallel, TwoProcessesTrainLikeOneWithDropout) { expect_like_one_process(2, 4, false); }

TEST(DataParallel, WeightedLossAndBatchesSmallerThanTheGroup) {
  // 3 processes, batch 2: one shard of every batch is empty (it still draws the masks).
  expect_like_one_process(3, 2, true);
}

TEST(DataParallel, ABufferedSampleStreamTrainsLikeOneProcess) {
  // 9 training samples through a buffer of 3: every process draws the same plan and takes
  // the whole batch off its stream, copying only its shard.
  expect_like_one_process(2, 4, true, 3);
}

TEST(DataParallel, GroupOfOneIsTheOneProcessRun) {
  const auto data = make_data(6, 13, false);
  TrainDef def;
  def.epochs = 1;
  def.batch_size = 4;
  const std::vector<TrainRun> solo = train_parallel(1, data, def);
  const TrainRun plain = train(data, def, nullptr);
  EXPECT_EQ(std::memcmp(solo[0].weights.data(), plain.weights.data(), sizeof(float) * plain.weights.size()), 0);
}

}  // namespace
}  // namespace dc
