// Google Benchmarks of the CNN hot paths (dc_learning):
//   conv2d_forward / conv2d_backward   61 × 61, 16→32 channels, k3, stride 1 or 2, batch 1 or 32
//   unet_small/infer_b1                 default U-Net (4 in, 2 out, 61 × 61) inference, batch 1
//   unet_small/train_step_b32           forward + weighted-free MSE + backward + SGD step, batch 32
//   unet_deep/infer_b1, unet_deep_slim/infer_b1, unet_fast/infer_b1
//                                       the arch files models/arch/unet-{deep,deep-slim,fast}.toml with the
//                                       residual model's 10 input channels (the shipped model's
//                                       network), inference, batch 1
// Threads: OpenMP, set with OMP_NUM_THREADS (benchmarks/compare/torch_compare.py runs 1 and 2). Times are
// wall-clock (UseRealTime) because the work is spread over threads; "samples/s" counters
// give throughput. benchmarks/compare/torch_compare.py parses the unet_small entries of
// --benchmark_format=json to compare against PyTorch.
#include <benchmark/benchmark.h>

#include <string>

#include "dc/core/rng.hpp"
#include "dc/learning/arch.hpp"
#include "dc/learning/initializer.hpp"
#include "dc/learning/layers/conv2d.hpp"
#include "dc/learning/mse_loss.hpp"
#include "dc/learning/network.hpp"
#include "dc/learning/optimizer.hpp"

namespace {

void fill(dc::Tensor& t, dc::Rng& rng) {
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = static_cast<float>(rng.gaussian(1.0));
}

void conv_args(benchmark::internal::Benchmark* b) {
  for (int batch : {1, 32})
    for (int stride : {1, 2}) b->Args({batch, stride});
  b->ArgNames({"batch", "stride"})->UseRealTime()->Unit(benchmark::kMillisecond);
}

void BM_Conv2dForward(benchmark::State& state) {
  const int batch = static_cast<int>(state.range(0)), stride = static_cast<int>(state.range(1));
  dc::Rng rng(1);
  dc::Conv2d conv(16, 32, 3, stride, true);
  conv.initialize(dc::HeNormal(), rng);
  dc::Tensor x(batch, 16, 61, 61), y;
  fill(x, rng);
  for (auto _ : state) {
    conv.forward(x, y, false);
    benchmark::DoNotOptimize(y.data());
  }
  state.counters["samples/s"] = benchmark::Counter(double(batch), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Conv2dForward)->Name("conv2d_forward")->Apply(conv_args);

void BM_Conv2dBackward(benchmark::State& state) {
  const int batch = static_cast<int>(state.range(0)), stride = static_cast<int>(state.range(1));
  dc::Rng rng(1);
  dc::Conv2d conv(16, 32, 3, stride, true);
  conv.initialize(dc::HeNormal(), rng);
  dc::Tensor x(batch, 16, 61, 61), y, dx;
  fill(x, rng);
  conv.forward(x, y, false);
  dc::Tensor dy(y.shape());
  fill(dy, rng);
  for (auto _ : state) {
    conv.backward(x, y, dy, &dx);  // dW, db and dx
    benchmark::DoNotOptimize(dx.data());
  }
  state.counters["samples/s"] = benchmark::Counter(double(batch), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Conv2dBackward)->Name("conv2d_backward")->Apply(conv_args);

void BM_UnetInfer(benchmark::State& state) {
  dc::Rng rng(2);
  dc::Network net(dc::default_arch(), dc::Shape{1, 4, 61, 61});
  net.initialize(dc::HeNormal(), rng);
  dc::Tensor x(1, 4, 61, 61);
  fill(x, rng);
  for (auto _ : state) benchmark::DoNotOptimize(net.forward(x, false).data());
  state.counters["samples/s"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["params"] = static_cast<double>(net.parameter_count());
}
BENCHMARK(BM_UnetInfer)->Name("unet_small/infer_b1")->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_ArchFileInfer(benchmark::State& state, const char* file) {
  dc::Rng rng(2);
  dc::Network net(dc::ArchSpec::load(std::string(DC_SOURCE_DIR) + "/models/arch/" + file), dc::Shape{1, 10, 61, 61});
  net.initialize(dc::HeNormal(), rng);
  dc::Tensor x(1, 10, 61, 61);
  fill(x, rng);
  for (auto _ : state) benchmark::DoNotOptimize(net.forward(x, false).data());
  state.counters["samples/s"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["params"] = static_cast<double>(net.parameter_count());
}
BENCHMARK_CAPTURE(BM_ArchFileInfer, deep, "unet-deep.toml")
    ->Name("unet_deep/infer_b1")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ArchFileInfer, slim, "unet-deep-slim.toml")
    ->Name("unet_deep_slim/infer_b1")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ArchFileInfer, fast, "unet-fast.toml")
    ->Name("unet_fast/infer_b1")->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_UnetTrainStep(benchmark::State& state) {
  const int batch = 32;
  dc::Rng rng(3);
  dc::Network net(dc::default_arch(), dc::Shape{1, 4, 61, 61});
  net.initialize(dc::HeNormal(), rng);
  net.set_rng(&rng);
  dc::Tensor x(batch, 4, 61, 61), t(batch, 2, 61, 61), g;
  fill(x, rng);
  fill(t, rng);
  dc::Sgd sgd(dc::SgdDef{0.9, 1e-4});
  auto params = net.parameters();
  const dc::MseLoss mse;
  for (auto _ : state) {
    const dc::Tensor& y = net.forward(x, true);
    benchmark::DoNotOptimize(mse(y, t, nullptr, &g));
    net.backward(g);
    sgd.step(params, 5e-3);
  }
  state.counters["samples/s"] = benchmark::Counter(double(batch), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_UnetTrainStep)->Name("unet_small/train_step_b32")->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
