#include "dc/bench/bench_merge.hpp"

#include "dc/core/error.hpp"

namespace dc::bench {
namespace {

template <class T>
void append(std::vector<T>& to, const std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

void append(StarterRecord& t, const StarterRecord& f) {
  append(t.seed, f.seed);
  append(t.step, f.step);
  append(t.rows, f.rows);
  append(t.sweeps_to_tol, f.sweeps_to_tol);
  append(t.sweeps_to_tol_high, f.sweeps_to_tol_high);
  append(t.warmstart_ms, f.warmstart_ms);
  append(t.oracle_ms, f.oracle_ms);
  append(t.solve_ms, f.solve_ms);
  append(t.sweep_ns_per_row, f.sweep_ns_per_row);
  append(t.initial_error, f.initial_error);
  t.theta.append(f.theta);  // offsets only when both share the scratch file
  append(t.residual, f.residual);
  append(t.lambda_error, f.lambda_error);
  append(t.penetration, f.penetration);
  append(t.energy_error, f.energy_error);
}

void append(SolverPairRecord& t, const SolverPairRecord& f) {
  append(t.seed, f.seed);
  append(t.iterations_to_accuracy, f.iterations_to_accuracy);
  append(t.ms_to_accuracy, f.ms_to_accuracy);
  append(t.total_ms, f.total_ms);
  append(t.final_accuracy, f.final_accuracy);
  append(t.weight_scale, f.weight_scale);
  append(t.factorizations, f.factorizations);
  append(t.outer_passes, f.outer_passes);
  append(t.factorizations_to_accuracy, f.factorizations_to_accuracy);
  append(t.newton_to_accuracy, f.newton_to_accuracy);
  // f's step k spans f.trace_offsets[k] … [k+1] − 1 of its own trace: shift by what t holds.
  const std::size_t shift = t.trace_ms.size();
  for (std::size_t k = 1; k < f.trace_offsets.size(); ++k) t.trace_offsets.push_back(shift + f.trace_offsets[k]);
  append(t.trace_ms, f.trace_ms);
  append(t.trace_accuracy, f.trace_accuracy);
}

}  // namespace

void append_results(BenchResults& to, const BenchResults& from) {
  if (from.starters.size() != to.starters.size())
    throw IoError("bench: the runs to join report different starter lists");
  if (from.pairs.size() != to.pairs.size()) throw IoError("bench: the runs to join report different solver comparisons");
  append(to.step_seed, from.step_seed);
  append(to.step_index, from.step_index);
  append(to.step_rows, from.step_rows);
  append(to.oracle_ms, from.oracle_ms);
  append(to.oracle_residual, from.oracle_residual);
  to.skipped_steps += from.skipped_steps;
  append(to.collide_ms, from.collide_ms);
  append(to.assemble_ms, from.assemble_ms);
  append(to.integrate_ms, from.integrate_ms);
  for (std::size_t i = 0; i < to.starters.size(); ++i) {
    if (to.starters[i].name != from.starters[i].name)
      throw IoError("bench: the runs to join report different starter lists");
    append(to.starters[i], from.starters[i]);
  }
  for (std::size_t i = 0; i < to.pairs.size(); ++i) append(to.pairs[i], from.pairs[i]);
}

}  // namespace dc::bench
