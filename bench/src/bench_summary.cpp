#include "dc/bench/bench_summary.hpp"

#include <algorithm>

namespace dc::bench {

std::vector<StarterSummary> summarise(const BenchResults& r) {
  std::vector<StarterSummary> out;
  const int never = r.options.sweeps + 1;
  for (const StarterRecord& rec : r.starters) {
    StarterSummary s;
    s.name = rec.name;
    s.uses_oracle = rec.uses_oracle;
    std::vector<double> sw, total;
    int unconv = 0;
    for (std::size_t k = 0; k < rec.sweeps_to_tol.size(); ++k) {
      const int v = rec.sweeps_to_tol[k];
      if (v < 0) ++unconv;
      sw.push_back(v < 0 ? never : v);
      total.push_back(rec.warmstart_ms[k] + rec.solve_ms[k]);
    }
    s.sweeps_to_tol = quartiles(sw);
    s.median_sweeps_to_tol = s.sweeps_to_tol.median;
    s.unconverged_share = sw.empty() ? 0.0 : static_cast<double>(unconv) / static_cast<double>(sw.size());
    s.warmstart_ms = quartiles(rec.warmstart_ms).median;
    // An oracle starter in paired mode uses the shared oracle: its cost is that one's.
    s.oracle_ms = rec.uses_oracle && r.options.mode == Mode::Paired ? quartiles(r.oracle_ms).median
                                                                    : quartiles(rec.oracle_ms).median;
    s.solve_ms = quartiles(rec.solve_ms).median;
    s.total_ms = quartiles(total).median;
    s.ns_per_row_sweep = quartiles(rec.sweep_ns_per_row).median;
    s.initial_error = quartiles(rec.initial_error).median;
    const std::size_t nb = r.budgets.size();
    const auto bi = static_cast<std::size_t>(std::find(r.budgets.begin(), r.budgets.end(), r.options.budget) - r.budgets.begin());
    std::vector<double> at_b, at_cap;
    for (std::size_t k = 0; nb > 0 && k + 1 <= rec.residual.size() / nb; ++k) {
      if (bi < nb) at_b.push_back(rec.residual[k * nb + bi]);
      at_cap.push_back(rec.residual[k * nb + nb - 1]);
    }
    s.residual_at_budget = quartiles(at_b).median;
    s.residual_at_cap = quartiles(at_cap).median;
    if (!rec.sweeps_to_tol_high.empty()) {
      std::vector<double> hi;
      int un = 0;
      for (const int v : rec.sweeps_to_tol_high) {
        if (v < 0) ++un;
        hi.push_back(v < 0 ? r.options.max_sweeps + 1 : v);
      }
      s.median_sweeps_high = quartiles(hi).median;
      s.unconverged_share_high = static_cast<double>(un) / static_cast<double>(hi.size());
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace dc::bench
