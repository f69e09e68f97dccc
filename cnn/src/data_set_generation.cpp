// generate_data_set: parallel simulations, one shard each, the manifest at the end
// (data_set_generation.hpp; the layout: data_set_shards.hpp).
#include "dc/cnn/data_set_generation.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <ctime>
#include <exception>
#include <filesystem>
#include <mutex>
#include <optional>

#include "data_set_shards.hpp"
#include "dc/core/error.hpp"
#include "dc/io/output_lock.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;
using namespace dataset;

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void check_settings(const DataSetGenerationDef& def) {
  if (def.simulations < 1) throw ConfigError("--sims must be >= 1 (got " + std::to_string(def.simulations) + ")");
  if (def.out.empty()) throw ConfigError("--out is required");
  if (def.threads < 0) throw ConfigError("--threads must be >= 1");
  def.params.validate();
}

/// Process 0, holding OUT.lock: everything that can be refused is refused before a
/// simulation runs. A stale OUT.partial without --resume is refused rather than replaced:
/// its run holds committed simulations. Returns the run id; `discarded` counts the removed
/// incomplete shards of an interrupted run.
std::string prepare_run(const DataSetGenerationDef& def, int& discarded) {
  const std::string marker = def.out + ".partial";
  // A run killed between its manifest's rename and the marker's removal is complete: its
  // resume just finishes the cleanup (and rewrites the same manifest).
  const bool own_manifest = def.resume && fs::exists(marker) && fs::exists(def.out) &&
                            manifest_names_run(def.out, read_run_marker(def.out));
  if (fs::exists(def.out) && !def.force && !own_manifest)
    throw ConfigError(def.out + " exists; use --force to replace it");
  if (def.resume && !fs::exists(marker))
    throw ConfigError("--resume: " + marker + " does not exist (nothing to resume; run without --resume)");
  if (!def.resume && fs::exists(marker))
    throw ConfigError(marker + " exists (an interrupted run): add --resume to continue it, or delete it");
  if (fs::exists(def.out) && !fs::is_regular_file(def.out))
    throw ConfigError(def.out + " exists and is not a file");
  if (!def.resume) {
    const std::string run = new_run_id();
    fs::create_directories(shard_dir(def.out, run));
    write_run_marker(def.out, run);
    return run;
  }
  const std::string run = read_run_marker(def.out);
  const std::string dir = shard_dir(def.out, run);
  fs::create_directories(dir);
  const ShardScan scan = scan_shards(dir);
  for (const std::string& tmp : scan.incomplete) fs::remove(tmp);
  discarded = static_cast<int>(scan.incomplete.size());
  if (!scan.committed.empty()) check_shard_params(dir, scan.committed.front(), def.params);
  return run;
}

/// The workers of one process: each takes the next simulation of `todo`, runs it, writes its
/// shard and reports it; the first failure stops the others and is rethrown.
class ShardWorkers {
 public:
  ShardWorkers(const DataSetGenerationDef& def, const DataSetGenerationHooks& hooks, const SimulationGenerator& gen,
               std::string dir, std::vector<int> todo, DataSetGenerationReport& report)
      : def_(def), hooks_(hooks), gen_(gen), dir_(std::move(dir)), todo_(std::move(todo)), report_(report) {}

  void run(int threads) {
#pragma omp parallel num_threads(threads)
    {
      try {
        while (work_one()) {
        }
      } catch (...) {
        std::lock_guard lock(mutex_);
        if (!failure_) failure_ = std::current_exception();
        failed_ = true;
      }
    }
    if (failure_) std::rethrow_exception(failure_);
  }

  [[nodiscard]] int written() const { return written_; }

 private:
  [[nodiscard]] bool keep_going() const {
    return !failed_.load(std::memory_order_relaxed) && (!hooks_.keep_going || hooks_.keep_going());
  }

  bool work_one() {
    const std::size_t k = next_.fetch_add(1);
    if (k >= todo_.size() || !keep_going()) return false;
    const std::optional<SimulationRecord> rec = gen_.run(todo_[k], [this] { return keep_going(); });
    if (!rec) return false;  // stopped: the unfinished simulation is dropped
    const auto w0 = std::chrono::steady_clock::now();
    const double c0 = thread_cpu_seconds();
    write_shard(dir_, def_.params, *rec);  // complete under its final name, or absent
    const double wall = seconds_since(w0), cpu = thread_cpu_seconds() - c0;
    std::lock_guard lock(mutex_);
    report_.write_seconds += wall;
    report_.write_cpu_seconds += cpu;
    report_.steps += def_.params.scene.time.steps;
    report_.samples += static_cast<std::int64_t>(rec->samples());
    report_.worst_residual = std::max(report_.worst_residual, rec->max_residual);
    ++written_;
    if (hooks_.on_committed) hooks_.on_committed(*rec);
    return true;
  }

  const DataSetGenerationDef& def_;
  const DataSetGenerationHooks& hooks_;
  const SimulationGenerator& gen_;
  const std::string dir_;
  const std::vector<int> todo_;
  DataSetGenerationReport& report_;
  std::atomic<std::size_t> next_{0};
  std::atomic<bool> failed_{false};
  std::mutex mutex_;  // guards report_, written_, failure_ and the on_committed calls
  std::exception_ptr failure_;
  int written_ = 0;
};

/// Process 0 after every process stopped: the manifest when all M shards are in, then the
/// marker and the shards of a replaced data set go.
void finish_run(const DataSetGenerationDef& def, const std::string& run, DataSetGenerationReport& report) {
  const std::string dir = shard_dir(def.out, run);
  const ShardScan scan = scan_shards(dir);
  report.completed = static_cast<int>(std::count_if(scan.committed.begin(), scan.committed.end(),
                                                    [&](int i) { return i < def.simulations; }));
  if (report.completed < def.simulations) return;
  const auto t0 = std::chrono::steady_clock::now();
  report.samples = write_manifest(def.out, run, def.params, def.simulations);
  report.manifest_seconds = seconds_since(t0);
  report.finished = true;
  report.path = def.out;
  fs::remove(def.out + ".partial");
  for (const auto& entry : fs::directory_iterator(shard_root(def.out)))
    if (entry.path().filename() != run) fs::remove_all(entry.path());
}

}  // namespace

DataSetGenerationReport generate_data_set(const DataSetGenerationDef& def, const DataSetGenerationHooks& hooks,
                                          const DataSetPartition& part) {
  check_settings(def);
  const bool leader = part.rank == 0, parallel = part.processes > 1;
  if (parallel && (!part.broadcast || !part.sum)) throw InvalidArgument("generate_data_set: a partition needs broadcast and sum");
  DataSetGenerationReport report;
  std::optional<OutputLock> lock;
  std::string run;
  if (leader) {
    lock.emplace(def.out);  // IoError naming the holder when another run writes OUT
    run = prepare_run(def, report.discarded);
  }
  if (parallel) run = part.broadcast(run);  // an error above ends the job (MPI_Abort in main)
  const std::string dir = shard_dir(def.out, run);
  report.path = dir;

  // The simulations still to do, of this process's share.
  const ShardScan scan = scan_shards(dir);
  std::vector<bool> done(static_cast<std::size_t>(def.simulations), false);
  for (const int i : scan.committed)
    if (i < def.simulations) done[static_cast<std::size_t>(i)] = true;
  report.first = static_cast<int>(std::count(done.begin(), done.end(), true));
  std::vector<int> todo;
  for (int i = 0; i < def.simulations; ++i)
    if (!done[static_cast<std::size_t>(i)] && i % part.processes == part.rank) todo.push_back(i);

  report.threads = def.threads > 0 ? def.threads : std::max(1, omp_get_max_threads());
  if (hooks.on_start) hooks.on_start(report.first, report.threads);
  const auto t0 = std::chrono::steady_clock::now();
  const SimulationGenerator generator(def.params);
  ShardWorkers workers(def, hooks, generator, dir, std::move(todo), report);
  workers.run(report.threads);
  report.wall_seconds = seconds_since(t0);
  report.completed = report.first + workers.written();

  if (parallel) (void)part.sum(workers.written());  // every process has stopped writing
  if (leader) finish_run(def, run, report);
  if (parallel) report.finished = part.broadcast(report.finished ? "finished" : "incomplete") == "finished";
  if (report.finished) report.path = def.out;
  return report;
}

}  // namespace dc
