// Google Benchmark of the whole `cnn` warm start (docs/design.md §5): feature image +
// inference + Shepard read-back at the contacts, on the seed scene, batch 1, one thread —
// what `deepcontact bench` times as the cnn's warm start. Families: cnn_warm_start (the
// starter's own split), cnn_warm_start_parts (each part in thread CPU µs, plus the unfused
// network), cnn_warm_start_predict_all (the whole-grid read-back), cnn_layers (per network
// node), cnn_plan_steps (per fused-plan step); benchmark list and counters in docs/bench.md
// "Micro benchmarks". Models: DC_CNN_MODELS (comma-separated files), default
// DC_SOURCE_DIR/models/default.h5. Time: CPU time of the one thread.
//   build/bin/micro_cnn --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <omp.h>

#include <ctime>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "dc/cnn/cnn_warm_starter.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "dc/learning/labels.hpp"
#include "dc/learning/model_file.hpp"
#include "dc/sph/sph_grid.hpp"
#include "dc/warmstart/sph_warm_starter.hpp"

namespace {

/// The seed scene after `steps` steps (builtin warm start, 300 PGS sweeps), collided and
/// assembled: previous_contacts() carry the solved λ, as in the bench. Built once per k.
const dc::World& seed_world(int steps) {
  static std::map<int, std::unique_ptr<dc::World>> cache;
  auto& w = cache[steps];
  if (!w) {
    w = std::make_unique<dc::World>(dc::default_world_def());
    const auto solver = dc::make_solver("pgs");
    dc::SolverOptions o;
    o.max_sweeps = 300;
    o.tolerance = 1e-2;
    o.record_theta = false;
    for (int k = 0; k < steps; ++k) {
      w->step(*solver, o, [](const dc::World& world) {
        Eigen::VectorXd l = Eigen::VectorXd::Zero(world.problem().rows());
        const auto& cur = world.contacts();
        const auto match = dc::match_contacts_by_key(world.previous_contacts(), cur);
        for (std::size_t c = 0; c < cur.size(); ++c)
          if (match[c] >= 0) {
            const dc::Contact& p = world.previous_contacts()[static_cast<std::size_t>(match[c])];
            world.constraints().put(static_cast<int>(c), p.lambda_n, p.lambda_t, l);
          }
        return l;
      });
    }
    w->collide();
    w->assemble();
  }
  return *w;
}

/// CPU time of this thread [ms]: the per-part counters stay meaningful on a loaded machine.
double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

/// The starter's model, a feature-image builder of its grid on the scene's box and the
/// feature tensor: what the part-by-part benchmarks run the pipeline with (1 thread).
struct StarterParts {
  std::unique_ptr<dc::CnnWarmStarter> starter;
  dc::FeatureImageDef def;
  std::optional<dc::FeatureImageBuilder> builder;
  dc::Tensor features;
  bool residual = false;

  StarterParts(const std::string& path, const dc::World& world)
      : starter(dc::CnnWarmStarter::load(path, "cnn", false)), def(starter->model().grid().image) {
    omp_set_num_threads(1);
    def.sph.grid.width = world.def().world.width;
    def.sph.grid.height = world.def().world.height;
    builder.emplace(def);
    features = dc::Tensor(1, builder->feature_channels(), builder->ny(), builder->nx());
    residual = starter->model().grid().labels.kind == dc::LabelKind::Residual;
  }
};

/// The stencil nodes of the world's contacts, as the starter lists them (its list is private).
std::vector<int> stencil_pixels(const dc::FeatureImageDef& def, const dc::World& world) {
  std::vector<int> pixels;
  dc::SphGrid g(dc::SphGridDef{def.sph.grid.width, def.sph.grid.height, def.sph.grid.spacing, 1});
  std::vector<char> seen(static_cast<std::size_t>(g.nx() * g.ny()), 0);
  for (const dc::Contact& c : world.contacts()) {
    const dc::BilinearStencil st = g.stencil(c.point);
    for (int j : {st.j0, st.j1})
      for (int i : {st.i0, st.i1})
        if (!seen[static_cast<std::size_t>(j * g.nx() + i)]++) pixels.push_back(j * g.nx() + i);
  }
  return pixels;
}

/// features → network_output_at → guess_from_output, each part timed in CPU ms: the
/// starter's initial_guess without the residual add (its own split is wall time).
void BM_CnnWarmStartParts(benchmark::State& state, std::string path, int steps) {
  const dc::World& world = seed_world(steps);
  StarterParts parts(path, world);
  dc::CnnWarmStarter* starter = parts.starter.get();
  dc::Model& model = starter->model();
  const dc::FeatureImageDef& def = parts.def;
  dc::FeatureImageBuilder& builder = *parts.builder;
  dc::Tensor& features = parts.features;
  const bool residual = parts.residual;
  const std::vector<int> pixels = stencil_pixels(def, world);
  dc::InferencePlan& plan = starter->inference_plan(world);
  // As initial_guess: the key match done once (also needed by the residual add), the
  // builder's nonzero rows handed to the plan.
  const std::vector<int> match = dc::match_contacts_by_key(world.previous_contacts(), world.contacts());
  double f = 0, n = 0, u = 0, r = 0;
  for (auto _ : state) {
    const double t0 = cpu_ms();
    builder.features(world.bodies(), world.contacts(), world.previous_contacts(), &world.problem(),
                     std::span<float>(features.data(), features.size()), match);
    const double t1 = cpu_ms();
    const auto [lo, hi] = builder.nonzero_rows();
    const dc::Tensor& y = plan.run(features, pixels, dc::InferencePlan::InputRows{lo, hi});
    const double t2 = cpu_ms();
    benchmark::DoNotOptimize(starter->guess_from_output(world, y, !residual, builder.contact_weights()).data());
    const double t3 = cpu_ms();
    // The unfused network (standardise a copy, Network::forward_at) on the same features,
    // side by side in the same iteration; its output is not read back.
    benchmark::DoNotOptimize(model.network_output_at(features, pixels).data());
    const double t4 = cpu_ms();
    f += t1 - t0;
    n += t2 - t1;
    r += t3 - t2;
    u += t4 - t3;
  }
  const double it = static_cast<double>(state.iterations());
  state.counters["cpu_us_features"] = 1e3 * f / it;
  state.counters["cpu_us_network"] = 1e3 * n / it;
  state.counters["cpu_us_network_unfused"] = 1e3 * u / it;
  state.counters["cpu_us_readback"] = 1e3 * r / it;
  state.counters["fused"] = plan.fused() ? 1 : 0;
  state.counters["stencil_nodes"] = static_cast<double>(pixels.size());
}

void BM_CnnWarmStart(benchmark::State& state, std::string path, int steps) {
  const dc::World& world = seed_world(steps);
  auto starter = dc::CnnWarmStarter::load(path, "cnn", false);
  const dc::StepView view{world};
  benchmark::DoNotOptimize(starter->initial_guess(view).data());  // first call sizes the buffers
  const dc::CnnTiming before = starter->total_timing();
  for (auto _ : state) benchmark::DoNotOptimize(starter->initial_guess(view).data());
  const dc::CnnTiming& t = starter->total_timing();
  const double calls = static_cast<double>(t.calls - before.calls);
  state.counters["features_ms"] = (t.features_ms - before.features_ms) / calls;
  state.counters["inference_ms"] = (t.inference_ms - before.inference_ms) / calls;
  state.counters["gather_ms"] = (t.gather_ms - before.gather_ms) / calls;
  state.counters["contacts"] = static_cast<double>(world.contacts().size());
}

// The whole-grid pipeline: Model::predict (de-standardise and s·sinh at every node), the
// whole label grid copied, then the read-back (guess_from_labels); the residual correction's
// final add/projection is left out. Same features and network.
void BM_CnnWarmStartPredictAll(benchmark::State& state, std::string path, int steps) {
  const dc::World& world = seed_world(steps);
  StarterParts p(path, world);
  for (auto _ : state) {
    p.builder->features(world.bodies(), world.contacts(), world.previous_contacts(),
                         std::span<float>(p.features.data(), p.features.size()));
    const dc::Tensor labels = p.starter->model().predict(p.features);
    benchmark::DoNotOptimize(p.starter->guess_from_labels(world, labels, !p.residual).data());
  }
}

void BM_CnnLayers(benchmark::State& state, std::string path, int steps) {
  const dc::World& world = seed_world(steps);
  dc::Model model = dc::load_model(path);
  omp_set_num_threads(1);
  // The starter's feature image of this step.
  dc::FeatureImageDef def = model.grid().image;
  def.sph.grid.width = world.def().world.width;
  def.sph.grid.height = world.def().world.height;
  dc::FeatureImageBuilder builder(def);
  dc::Tensor features(1, builder.feature_channels(), builder.ny(), builder.nx()), x;
  builder.features(world.bodies(), world.contacts(), world.previous_contacts(),
                   std::span<float>(features.data(), features.size()));
  dc::Network& net = model.network();
  std::vector<double> node_ms, sum(net.size(), 0.0);
  double standardise = 0, destandardise = 0;
  dc::Tensor y;
  for (auto _ : state) {
    const double t0 = cpu_ms();
    x = features;
    model.input_stats.apply(x);
    const double t1 = cpu_ms();
    y = net.forward(x, false, &node_ms);
    const double t2 = cpu_ms();
    model.output_stats.invert(y);
    dc::expand_labels(y, model.grid().labels.scale);
    benchmark::DoNotOptimize(y.data());
    const double t3 = cpu_ms();
    standardise += t1 - t0;
    destandardise += t3 - t2;
    for (std::size_t i = 0; i < node_ms.size(); ++i) sum[i] += node_ms[i];
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["us_standardise"] = 1e3 * standardise / n;
  for (std::size_t i = 0; i < sum.size(); ++i) state.counters["us_" + net.node_name(i)] = 1e3 * sum[i] / n;
  state.counters["us_destandardise"] = 1e3 * destandardise / n;
}

// The starter's fused InferencePlan step by step (each conv with its gather of padded
// input rows: standardisation, concatenation and upsampling included; the sparse head):
// one counter per step in thread CPU µs (mean per call), at the stencil nodes.
void BM_CnnPlanSteps(benchmark::State& state, std::string path, int steps) {
  const dc::World& world = seed_world(steps);
  StarterParts p(path, world);
  const std::vector<int> pixels = stencil_pixels(p.def, world);
  p.builder->features(world.bodies(), world.contacts(), world.previous_contacts(),
                      std::span<float>(p.features.data(), p.features.size()));
  dc::InferencePlan& plan = p.starter->inference_plan(world);
  std::vector<double> step_ms, sum(plan.step_count(), 0.0);
  const auto [lo, hi] = p.builder->nonzero_rows();  // as initial_guess: no scan for empty rows
  for (auto _ : state) {
    benchmark::DoNotOptimize(plan.run(p.features, pixels, dc::InferencePlan::InputRows{lo, hi}, &step_ms).data());
    for (std::size_t i = 0; i < step_ms.size(); ++i) sum[i] += step_ms[i];
  }
  const double n = static_cast<double>(state.iterations());
  for (std::size_t i = 0; i < sum.size(); ++i) state.counters["us_" + plan.step_name(i)] = 1e3 * sum[i] / n;
  state.counters["fused"] = plan.fused() ? 1 : 0;
}

std::vector<std::string> model_paths() {
  const char* env = std::getenv("DC_CNN_MODELS");
  if (env == nullptr || *env == '\0') return {std::string(DC_SOURCE_DIR) + "/models/default.h5"};
  std::vector<std::string> out;
  std::stringstream ss(env);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  for (const std::string& path : model_paths()) {
    const std::string stem = std::filesystem::path(path).stem().string();
    for (int steps : {150, 400}) {
      const std::string tail = "/" + stem + "/step:" + std::to_string(steps);
      benchmark::RegisterBenchmark(("cnn_warm_start" + tail).c_str(), BM_CnnWarmStart, path, steps)
          ->Unit(benchmark::kMicrosecond);
      benchmark::RegisterBenchmark(("cnn_warm_start_parts" + tail).c_str(), BM_CnnWarmStartParts, path, steps)
          ->Unit(benchmark::kMicrosecond);
      benchmark::RegisterBenchmark(("cnn_warm_start_predict_all" + tail).c_str(), BM_CnnWarmStartPredictAll, path,
                                   steps)
          ->Unit(benchmark::kMicrosecond);
      benchmark::RegisterBenchmark(("cnn_layers" + tail).c_str(), BM_CnnLayers, path, steps)
          ->Unit(benchmark::kMicrosecond);
      benchmark::RegisterBenchmark(("cnn_plan_steps" + tail).c_str(), BM_CnnPlanSteps, path, steps)
          ->Unit(benchmark::kMicrosecond);
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
