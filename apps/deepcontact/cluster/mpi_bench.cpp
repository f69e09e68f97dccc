// run_bench_across_ranks (mpi_bench.hpp).
#include "cluster/mpi_bench.hpp"

#include <chrono>
#include <memory>
#include <span>

#include "cluster/byte_buffer.hpp"
#include "cluster/comm.hpp"
#include "dc/bench/bench_merge.hpp"
#include "dc/core/error.hpp"
#include "dc/io/scratch_file.hpp"

namespace dc::cli {
namespace {

using Clock = std::chrono::steady_clock;

// A starter's θ rows travel as (row length, every value); the receiver appends them to its own
// scratch file (theta_rows.hpp). `send_theta` false: sent as none (rank 0 keeps its own rows).
template <class Io>
void theta_field(const Io& io, bench::ThetaRows& t, bool send_theta, const std::shared_ptr<ScratchFile>& scratch) {
  std::uint64_t length = t.row_length();
  std::vector<float> values = send_theta ? t.all() : std::vector<float>{};  // empty when unpacking
  io(length);
  io(values);
  if (t.rows() > 0 || values.empty()) return;  // packed, or nothing received
  if (length == 0 || values.size() % length != 0) throw IoError("bench: MPI message: theta rows of a wrong size");
  t = bench::ThetaRows(scratch);
  for (std::size_t i = 0; i < values.size(); i += length) t.append(std::span<const float>(values).subspan(i, length));
}

// Every per-step field of the results, in one fixed order (pack and unpack share it).
template <class Io>
void per_step_fields(const Io& io, bench::BenchResults& r, bool send_theta = true,
                     const std::shared_ptr<ScratchFile>& scratch = nullptr) {
  io(r.step_seed);
  io(r.step_index);
  io(r.step_rows);
  io(r.oracle_ms);
  io(r.oracle_residual);
  io(r.skipped_steps);
  io(r.collide_ms);
  io(r.assemble_ms);
  io(r.integrate_ms);
  std::uint64_t n = r.starters.size();
  io(n);
  r.starters.resize(static_cast<std::size_t>(n));
  for (bench::StarterRecord& s : r.starters) {
    io(s.name);
    io(s.uses_oracle);
    io(s.seed);
    io(s.step);
    io(s.rows);
    io(s.sweeps_to_tol);
    io(s.sweeps_to_tol_high);
    io(s.warmstart_ms);
    io(s.oracle_ms);
    io(s.solve_ms);
    io(s.sweep_ns_per_row);
    io(s.initial_error);
    theta_field(io, s.theta, send_theta, scratch);
    io(s.residual);
    io(s.lambda_error);
    io(s.penetration);
    io(s.energy_error);
  }
  std::uint64_t m = r.pairs.size();  // the solver comparison (--solvers)
  io(m);
  r.pairs.resize(static_cast<std::size_t>(m));
  for (bench::SolverPairRecord& q : r.pairs) {
    io(q.solver);
    io(q.starter);
    io(q.seed);
    io(q.iterations_to_accuracy);
    io(q.ms_to_accuracy);
    io(q.total_ms);
    io(q.final_accuracy);
    io(q.weight_scale);
    io(q.factorizations);
    io(q.outer_passes);
    io(q.factorizations_to_accuracy);
    io(q.newton_to_accuracy);
    io(q.trace_offsets);
    io(q.trace_ms);
    io(q.trace_accuracy);
  }
}

Bytes pack(bench::BenchResults& r, bool send_theta) {
  ByteWriter w;
  per_step_fields([&](auto& v) { w.put(v); }, r, send_theta);
  return w.take();
}

bench::BenchResults unpack(const Bytes& b, const std::shared_ptr<ScratchFile>& scratch) {
  bench::BenchResults r;
  ByteReader in(b);
  per_step_fields([&](auto& v) { in.get(v); }, r, true, scratch);
  if (!in.done()) throw IoError("bench: MPI message: trailing bytes");
  return r;
}

}  // namespace

bench::BenchResults run_bench_across_ranks(const bench::BenchOptions& o, const WarmStarterRegistry& registry,
                                           const bench::ProgressFn& progress, DistributedBenchTimes* times) {
  const Comm& comm = world();
  if (!comm.parallel()) {
    const auto t0 = Clock::now();
    bench::BenchResults r = bench::run_bench(o, registry, progress);
    if (times) times->run_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return r;
  }
  const auto t0 = Clock::now();
  const auto [begin, end] = block_of(o.seeds.size(), comm.rank(), comm.size());
  bench::BenchOptions mine = o;
  mine.seeds.assign(o.seeds.begin() + static_cast<std::ptrdiff_t>(begin), o.seeds.begin() + static_cast<std::ptrdiff_t>(end));
  bench::BenchResults local;
  if (!mine.seeds.empty()) {
    local = bench::run_bench(mine, registry, progress);  // every rank: it also polls for stop signals
  } else {
    // More ranks than seeds: validate the options as the others do (same errors everywhere),
    // contribute nothing.
    mine.seeds = {o.seeds.front()};
    mine.scene.time.steps = 0;
    local = bench::run_bench(mine, registry);
  }
  const auto t1 = Clock::now();
  comm.barrier();  // wait for the slowest rank without a busy loop, then gather
  // Rank 0 keeps its own θ rows where they are; the others' arrive in the messages.
  const std::vector<Bytes> all = comm.gather(pack(local, !comm.is_root()));
  if (!comm.is_root()) return local;
  // Rank 0's block comes first: its own results (the options as run_bench resolved them, e.g.
  // the default --budget; the report's reference frame is the first seed's, which it holds).
  bench::BenchResults merged = std::move(local);
  const auto scratch = std::make_shared<ScratchFile>(o.scratch_dir);
  for (std::size_t r = 1; r < all.size(); ++r) bench::append_results(merged, unpack(all[r], scratch));
  merged.options.seeds = o.seeds;  // every rank's
  merged.options.scene = o.scene;
  const auto t2 = Clock::now();
  merged.wall_seconds = std::chrono::duration<double>(t2 - t0).count();
  if (times) {
    times->run_seconds = std::chrono::duration<double>(t1 - t0).count();
    times->gather_seconds = std::chrono::duration<double>(t2 - t1).count();
  }
  return merged;
}

}  // namespace dc::cli
