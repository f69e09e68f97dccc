// generate_data_set: the ordered parallel pipeline (data_set_generation.hpp).
#include "dc/cnn/data_set_generation.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>

#include <ctime>

#include "dc/core/error.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Everything that can be refused is refused before a file is opened or a simulation runs:
/// the settings, then the state of OUT and OUT.partial (the writer's only; a shipper opens
/// no file). A stale OUT.partial without --resume is refused rather than replaced: it holds
/// an interrupted run's committed simulations.
void check_request(const DataSetGenerationDef& def, bool shipper, const std::string& partial) {
  if (def.simulations < 1) throw ConfigError("--sims must be >= 1 (got " + std::to_string(def.simulations) + ")");
  if (def.out.empty()) throw ConfigError("--out is required");
  if (def.threads < 0) throw ConfigError("--threads must be >= 1");
  def.params.validate();
  if (shipper) return;
  if (fs::exists(def.out) && !def.force) throw ConfigError(def.out + " exists; use --force to replace it");
  if (def.resume && !fs::exists(partial))
    throw ConfigError("--resume: " + partial + " does not exist (nothing to resume; run without --resume)");
  if (!def.resume && fs::exists(partial))
    throw ConfigError(partial + " exists (an interrupted run): add --resume to continue it, or delete it");
}

/// One run's workers and its writer (data_set_generation.hpp "Threads"): T workers simulate
/// the indices this process owns, at most `max_ahead` past the writer; finished simulations
/// wait in `ready_` until the writer (the calling thread, the only one that calls receive /
/// ship) appends them in index order. Everything below the mutex is guarded by it.
class OrderedPipeline {
 public:
  OrderedPipeline(const DataSetGenerationDef& def, const DataSetGenerationHooks& hooks, const DataSetPartition& part,
                  const SimulationGenerator& generator, DataSetWriter* writer, DataSetGenerationReport& report)
      : def_(def), hooks_(hooks), part_(part), generator_(generator), writer_(writer), report_(report),
        sims_(def.simulations), threads_(report.threads), max_ahead_(2 * report.threads * std::max(1, part.processes)),
        written_(report.first), next_(report.first) {}

  /// Runs the workers and the writer until every simulation is written, the run is stopped
  /// (keep_going, another process stopped) or something failed; rethrows the first failure
  /// after every thread has left.
  void run() {
    // T workers plus one writer thread (thread 0, the thread that called). If OpenMP grants
    // a single thread, it alternates: one simulation, then write it.
#pragma omp parallel num_threads(threads_ + 1)
    {
      const int id = omp_get_thread_num(), team = omp_get_num_threads();
      try {
        if (team == 1) {
          simulate_and_write_alternately();
        } else if (id == 0) {
          write_until_done(team);
        } else {
          while (work_one()) {
          }
        }
      } catch (...) {
        fail(std::current_exception());
      }
      if (team > 1 && id != 0) {
        std::lock_guard lock(mutex_);
        ++workers_done_;
        changed_.notify_all();
      }
    }
    if (failure_) std::rethrow_exception(failure_);
  }

  /// Simulations written (or shipped, or skipped as another process's) from index 0 on.
  [[nodiscard]] int written() const { return written_; }
  /// Simulations this run appended or shipped.
  [[nodiscard]] int shipped() const { return shipped_; }

 private:
  [[nodiscard]] bool shipper() const { return static_cast<bool>(part_.ship); }
  [[nodiscard]] bool here(int i) const { return !part_.simulates_here || part_.simulates_here(i); }

  /// Polled by the simulations between steps: false once anything failed, another process
  /// stopped, or the caller's keep_going said stop.
  [[nodiscard]] bool keep_going() const {
    return !failed_.load(std::memory_order_relaxed) && !remote_stopped_.load(std::memory_order_relaxed) &&
           (!hooks_.keep_going || hooks_.keep_going());
  }

  void fail(std::exception_ptr e) {
    std::lock_guard lock(mutex_);
    if (!failure_) failure_ = e;
    failed_ = true;
    changed_.notify_all();
  }

  /// Thread 0 of a team: writes whatever is ready, then waits for the next change. Leaves
  /// when all are written, on a failure or a remote stop, or when every worker has left and
  /// the next simulation is one of ours that nobody is computing (an interrupted run).
  void write_until_done(int team) {
    std::unique_lock lock(mutex_);
    for (;;) {
      write_ready(lock);
      if (written_ >= sims_ || failed_ || remote_stopped_) break;
      if (workers_done_ == team - 1 && writer_stuck()) break;
      changed_.wait(lock);
    }
  }

  /// A team of one thread: one simulation, then write what is ready, until nothing is left.
  void simulate_and_write_alternately() {
    for (;;) {
      const bool more = work_one();
      std::unique_lock lock(mutex_);
      write_ready(lock);
      if (!more || remote_stopped_) break;
    }
  }

  /// The writer cannot get further: its next simulation is one of ours that nobody is computing.
  [[nodiscard]] bool writer_stuck() const { return here(written_) && ready_.find(written_) == ready_.end(); }

  /// One simulation on the calling thread; false when the loop should stop. It waits while
  /// its index is max_ahead or more past the writer: that bounds the memory of `ready_`.
  bool work_one() {
    int i = next_.fetch_add(1);
    while (i < sims_ && !here(i)) i = next_.fetch_add(1);
    if (i >= sims_ || !keep_going()) return false;
    {
      std::unique_lock lock(mutex_);
      changed_.wait(lock, [&] { return i < written_ + max_ahead_ || !keep_going(); });
    }
    std::optional<SimulationRecord> rec = generator_.run(i, [this] { return keep_going(); });
    if (!rec) return false;  // interrupted or another thread failed: drop the partial simulation
    std::lock_guard lock(mutex_);
    ready_.emplace(i, std::move(*rec));
    changed_.notify_all();
    return true;
  }

  /// Appends (or ships) ready simulations in order and receives the others' in their turn;
  /// called by the writer thread only, with the lock held. Stops at this process's first
  /// unfinished simulation.
  void write_ready(std::unique_lock<std::mutex>& lock) {
    while (written_ < sims_) {
      std::optional<SimulationRecord> rec;
      if (!here(written_)) {
        if (shipper()) {  // another process's simulation: the writer gets it from there
          ++written_;
          changed_.notify_all();
          continue;
        }
        rec = receive_remote(lock);
      } else {
        rec = take_ready();
      }
      if (!rec) return;
      commit(*rec, lock);
    }
  }

  /// Our next simulation if a worker has finished it.
  std::optional<SimulationRecord> take_ready() {
    const auto it = ready_.find(written_);
    if (it == ready_.end()) return std::nullopt;
    std::optional<SimulationRecord> rec = std::move(it->second);
    ready_.erase(it);
    return rec;
  }

  /// Another process's simulation, received without the lock (it blocks until it arrives);
  /// nullopt when that process stopped, which stops this run too.
  std::optional<SimulationRecord> receive_remote(std::unique_lock<std::mutex>& lock) {
    if (remote_stopped_) return std::nullopt;
    lock.unlock();
    const auto r0 = std::chrono::steady_clock::now();
    std::optional<SimulationRecord> rec = part_.receive(written_);
    report_.receive_seconds += seconds_since(r0);
    lock.lock();
    if (!rec) {
      remote_stopped_ = true;
      changed_.notify_all();
    }
    return rec;
  }

  /// Appends `rec` to the file (rows, /sims with the seed last, flush), or ships it, without
  /// the lock so that the workers go on; then counts it as written.
  void commit(const SimulationRecord& rec, std::unique_lock<std::mutex>& lock) {
    lock.unlock();
    const auto w0 = std::chrono::steady_clock::now();
    const double c0 = thread_cpu_seconds();
    if (shipper()) {
      part_.ship(rec);
    } else {
      writer_->append(rec);
    }
    report_.write_seconds += seconds_since(w0);
    report_.write_cpu_seconds += thread_cpu_seconds() - c0;
    if (!shipper() && hooks_.on_committed) hooks_.on_committed(rec);
    lock.lock();
    ++written_;
    ++shipped_;
    report_.steps += def_.params.scene.time.steps;
    report_.worst_residual = std::max(report_.worst_residual, rec.max_residual);
    changed_.notify_all();
  }

  const DataSetGenerationDef& def_;
  const DataSetGenerationHooks& hooks_;
  const DataSetPartition& part_;
  const SimulationGenerator& generator_;
  DataSetWriter* const writer_;  // null for a shipper
  DataSetGenerationReport& report_;
  const int sims_, threads_, max_ahead_;

  std::mutex mutex_;                 // guards ready_, failure_, written_, workers_done_, shipped_, report_
  std::condition_variable changed_;  // a simulation finished / was written / a worker quit
  std::map<int, SimulationRecord> ready_;
  std::exception_ptr failure_;
  int written_;           // the next simulation to write (or to ship / skip)
  int workers_done_ = 0;  // workers that left their loop
  int shipped_ = 0;
  std::atomic<int> next_;  // the next index a worker takes
  std::atomic<bool> failed_{false}, remote_stopped_{false};
};

}  // namespace

DataSetGenerationReport generate_data_set(const DataSetGenerationDef& def, const DataSetGenerationHooks& hooks,
                                          const DataSetPartition& part) {
  const bool shipper = static_cast<bool>(part.ship);  // a non-writer process: no file
  const std::string partial = def.out + ".partial";
  check_request(def, shipper, partial);

  // Resume or create: the first simulation of this run is the file's committed count, agreed
  // with the other processes.
  const SimulationGenerator generator(def.params);
  std::optional<DataSetWriter> writer;
  if (!shipper)
    writer.emplace(def.resume ? DataSetWriter::resume(partial, def.params) : DataSetWriter::create(partial, def.params));
  DataSetGenerationReport report;
  report.first = writer ? writer->completed_simulations() : 0;
  if (part.agree_first) report.first = part.agree_first(report.first);
  report.threads = def.threads > 0 ? def.threads : std::max(1, omp_get_max_threads());
  if (hooks.on_start) hooks.on_start(report.first, report.threads);
  const auto t0 = std::chrono::steady_clock::now();

  OrderedPipeline pipeline(def, hooks, part, generator, writer ? &*writer : nullptr, report);
  pipeline.run();
  report.wall_seconds = seconds_since(t0);

  // The end: a shipper reports what it shipped; the writer closes the file and, when all M
  // simulations are in, renames OUT.partial to OUT.
  report.path = partial;
  if (shipper) {
    report.completed = report.first + pipeline.shipped();
    report.finished = pipeline.written() >= def.simulations;
    return report;
  }
  report.completed = writer->completed_simulations();
  report.samples = writer->samples();
  writer->close();
  report.finished = report.completed >= def.simulations;
  if (report.finished) {
    fs::rename(partial, def.out);
    report.path = def.out;
  }
  return report;
}

}  // namespace dc
