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
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
}  // namespace

DataSetGenerationReport generate_data_set(const DataSetGenerationDef& def, const DataSetGenerationHooks& hooks,
                                          const DataSetPartition& part) {
  namespace fs = std::filesystem;
  if (def.simulations < 1) throw ConfigError("--sims must be >= 1 (got " + std::to_string(def.simulations) + ")");
  if (def.out.empty()) throw ConfigError("--out is required");
  if (def.threads < 0) throw ConfigError("--threads must be >= 1");
  def.params.validate();
  const bool shipper = static_cast<bool>(part.ship);  // a non-writer process: no file
  const std::string partial = def.out + ".partial";
  if (!shipper) {
    if (fs::exists(def.out) && !def.force) throw ConfigError(def.out + " exists; use --force to replace it");
    if (def.resume && !fs::exists(partial))
      throw ConfigError("--resume: " + partial + " does not exist (nothing to resume; run without --resume)");
    if (!def.resume && fs::exists(partial))
      throw ConfigError(partial + " exists (an interrupted run): add --resume to continue it, or delete it");
  }

  const SimulationGenerator generator(def.params);
  std::optional<DataSetWriter> writer;
  if (!shipper)
    writer.emplace(def.resume ? DataSetWriter::resume(partial, def.params) : DataSetWriter::create(partial, def.params));
  DataSetGenerationReport report;
  report.first = writer ? writer->completed_simulations() : 0;
  if (part.agree_first) report.first = part.agree_first(report.first);
  report.threads = def.threads > 0 ? def.threads : std::max(1, omp_get_max_threads());
  const int sims = def.simulations, threads = report.threads;
  const auto here = [&](int i) { return !part.simulates_here || part.simulates_here(i); };
  if (hooks.on_start) hooks.on_start(report.first, threads);
  const auto t0 = std::chrono::steady_clock::now();

  std::mutex mutex;                 // guards ready, failure, written, workers_done, report
  std::condition_variable changed;  // a simulation finished / was written / a worker quit
  std::map<int, SimulationRecord> ready;
  std::exception_ptr failure;
  int written = report.first;  // the next simulation to write (or to ship / skip)
  int workers_done = 0;  // workers that left their loop
  int shipped = 0;
  std::atomic<int> next{report.first};
  std::atomic<bool> failed{false}, remote_stopped{false};
  const auto keep_going = [&] {
    return !failed.load(std::memory_order_relaxed) && !remote_stopped.load(std::memory_order_relaxed) &&
           (!hooks.keep_going || hooks.keep_going());
  };
  const int max_ahead = 2 * threads * std::max(1, part.processes);

  const auto fail = [&](std::exception_ptr e) {
    std::lock_guard lock(mutex);
    if (!failure) failure = e;
    failed = true;
    changed.notify_all();
  };
  // Appends (or ships) ready simulations in order and receives the others' in their turn;
  // called by the writer thread only. Stops at this process's first unfinished simulation.
  const auto write_ready = [&](std::unique_lock<std::mutex>& lock) {
    while (written < sims) {
      std::optional<SimulationRecord> rec;
      if (!here(written)) {
        if (shipper) {  // another process's simulation: the writer gets it from there
          ++written;
          changed.notify_all();
          continue;
        }
        if (remote_stopped) return;
        lock.unlock();
        const auto r0 = std::chrono::steady_clock::now();
        rec = part.receive(written);
        report.receive_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
        lock.lock();
        if (!rec) {
          remote_stopped = true;
          changed.notify_all();
          return;
        }
      } else {
        const auto it = ready.find(written);
        if (it == ready.end()) return;
        rec = std::move(it->second);
        ready.erase(it);
      }
      lock.unlock();
      const auto w0 = std::chrono::steady_clock::now();
      const double c0 = thread_cpu_seconds();
      if (shipper) {
        part.ship(*rec);
      } else {
        writer->append(*rec);  // rows, /sims (seed last), flush
      }
      report.write_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
      report.write_cpu_seconds += thread_cpu_seconds() - c0;
      if (!shipper && hooks.on_committed) hooks.on_committed(*rec);
      lock.lock();
      ++written;
      ++shipped;
      report.steps += def.params.scene.time.steps;
      report.worst_residual = std::max(report.worst_residual, rec->max_residual);
      changed.notify_all();
    }
  };
  // The writer cannot get further: its next simulation is one of ours that nobody is computing.
  const auto writer_stuck = [&] { return here(written) && ready.find(written) == ready.end(); };
  // One simulation on the calling thread; false when the loop should stop.
  const auto work_one = [&]() -> bool {
    int i = next.fetch_add(1);
    while (i < sims && !here(i)) i = next.fetch_add(1);
    if (i >= sims || !keep_going()) return false;
    {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return i < written + max_ahead || !keep_going(); });
    }
    std::optional<SimulationRecord> rec = generator.run(i, keep_going);
    if (!rec) return false;  // interrupted or another thread failed: drop the partial simulation
    std::lock_guard lock(mutex);
    ready.emplace(i, std::move(*rec));
    changed.notify_all();
    return true;
  };

  // T workers plus one writer thread (thread 0, the thread that called: the only one that
  // calls receive/ship). If OpenMP grants a single thread, it alternates: one simulation,
  // then write it.
#pragma omp parallel num_threads(threads + 1)
  {
    const int id = omp_get_thread_num(), team = omp_get_num_threads();
    try {
      if (team == 1) {
        for (;;) {
          const bool more = work_one();
          std::unique_lock lock(mutex);
          write_ready(lock);
          if (!more || remote_stopped) break;
        }
      } else if (id == 0) {
        std::unique_lock lock(mutex);
        for (;;) {
          write_ready(lock);
          if (written >= sims || failed || remote_stopped) break;
          if (workers_done == team - 1 && writer_stuck()) break;
          changed.wait(lock);
        }
      } else {
        while (work_one()) {
        }
      }
    } catch (...) {
      fail(std::current_exception());
    }
    if (team > 1 && id != 0) {
      std::lock_guard lock(mutex);
      ++workers_done;
      changed.notify_all();
    }
  }
  if (failure) std::rethrow_exception(failure);
  report.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  report.path = partial;
  if (shipper) {
    report.completed = report.first + shipped;
    report.finished = written >= sims;
    return report;
  }
  report.completed = writer->completed_simulations();
  report.samples = writer->samples();
  writer->close();
  report.finished = report.completed >= sims;
  if (report.finished) {
    fs::rename(partial, def.out);
    report.path = def.out;
  }
  return report;
}

}  // namespace dc
