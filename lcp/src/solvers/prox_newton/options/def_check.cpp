// Ranges of ProxNewtonDef's options (their meanings and defaults: dc/lcp/prox_newton.hpp).
#include "solvers/prox_newton/options/def_check.hpp"

#include <cmath>

#include "dc/core/error.hpp"

namespace dc::solvers::prox {

void check_def(const ProxNewtonDef& d) {
  const auto positive = [](double x) { return std::isfinite(x) && x > 0; };
  if (!positive(d.initial_shift) || !positive(d.min_shift) || !positive(d.max_shift) || d.min_shift > d.max_shift)
    throw InvalidArgument("prox-newton: shifts must be finite, > 0, min_shift <= max_shift");
  if (!(std::isfinite(d.shrink) && d.shrink > 1)) throw InvalidArgument("prox-newton: shrink must be > 1");
  if (!(d.pass_progress > 0 && d.pass_progress <= 1))
    throw InvalidArgument("prox-newton: pass_progress must be in (0, 1]");
  if (d.max_outer < 1 || d.inner_iterations < 1 || d.body_inner_iterations < 1 || d.max_stalls < 1)
    throw InvalidArgument("prox-newton: max_outer, inner_iterations, body_inner_iterations and max_stalls must be >= 1");
  if (!positive(d.cone_shift) || !positive(d.cone_min_shift) || !positive(d.cone_inner_tolerance) ||
      !(d.cone_shrink >= 1))
    throw InvalidArgument("prox-newton: cone_shift, cone_min_shift, cone_inner_tolerance must be > 0, cone_shrink >= 1");
  if (d.cone_inner_iterations < 1 || d.cone_follow_iterations < 1 || d.cone_max_stalls < 1 || d.cone_anderson < 0 ||
      d.cone_follow_after < 0 || d.cone_trust_retries < 0 || !(d.cone_trust_radius >= 0) || !(d.cone_trust_grow > 1) ||
      !(d.cone_follow_below >= 0) || !(d.cone_trust_forget >= 0) || !(d.cone_trust_accept >= 1))
    throw InvalidArgument("prox-newton: cone_inner_iterations, cone_follow_iterations, cone_max_stalls must be >= 1, "
                          "cone_anderson, cone_follow_after, cone_trust_retries, cone_trust_radius, cone_follow_below, cone_trust_forget >= 0, "
                          "cone_trust_grow > 1, cone_trust_accept >= 1");
  if (!positive(d.inner_tolerance)) throw InvalidArgument("prox-newton: inner_tolerance must be > 0");
  if (!(d.lead_window_bodies >= 0 && std::isfinite(d.lead_window_bodies)) || !(d.lead_initial_shift >= 0 && d.lead_initial_shift < 1))
    throw InvalidArgument("prox-newton: lead_window_bodies must be finite and >= 0, lead_initial_shift in [0, 1)");
  if (d.lead_sweeps < 0 || d.lead_finish_window < 0 || d.lead_newton_stalls < 0 || !(d.lead_gain >= 1) || d.lead_fallback_doublings > 20 ||
      d.lead_window < 0 || !(d.lead_window_gain > 1 && std::isfinite(d.lead_window_gain)) ||
      !(d.lead_window_gain_above > 1 && std::isfinite(d.lead_window_gain_above)) ||
      !(d.lead_fallback_cap_fall >= 0 && d.lead_fallback_cap_fall <= 1))
    throw InvalidArgument("prox-newton: lead_sweeps, lead_finish_window, lead_newton_stalls and lead_window must be >= 0, lead_gain >= 1, "
                          "lead_fallback_doublings <= 20, lead_window_gain(_above) finite and > 1, lead_fallback_cap_fall in [0, 1]");
  if (!(d.guess_fallback_cap_fall >= 0 && d.guess_fallback_cap_fall <= 1) || d.guess_floor_stalls < 0)
    throw InvalidArgument("prox-newton: guess_fallback_cap_fall must be in [0, 1], guess_floor_stalls >= 0");
  if (d.degenerate_drift_jumps < 0) throw InvalidArgument("prox-newton: degenerate_drift_jumps must be >= 0");
  if (!(d.degenerate_drift_linearity >= 0 && d.degenerate_drift_linearity < 1))
    throw InvalidArgument("prox-newton: degenerate_drift_linearity must be in [0, 1)");
  if (d.probe_sweeps < 0 || d.probe_iterations < 0)
    throw InvalidArgument("prox-newton: probe_sweeps and probe_iterations must be >= 0");
  if (!(d.probe_reach >= 0))
    throw InvalidArgument("prox-newton: probe_reach must be >= 0");
  if (d.probe_count < 0 || !(d.probe_refall >= 1 && std::isfinite(d.probe_refall)) ||
      !(d.probe_shift >= 0 && std::isfinite(d.probe_shift)))
    throw InvalidArgument("prox-newton: probe_count must be >= 0, probe_refall finite and >= 1, probe_shift finite and >= 0");
  if (d.lead_colored_rows < 0 || d.lead_stall_chunks < 0 || d.degenerate_stall_chunks < 0 || !(d.degenerate_rows > 0))
    throw InvalidArgument("prox-newton: lead_colored_rows, lead_stall_chunks, degenerate_stall_chunks must be >= 0, "
                          "degenerate_rows > 0");
  if (d.newton_budget < 0 || !(d.newton_budget_gain >= 1 && std::isfinite(d.newton_budget_gain)) ||
      !(d.newton_budget_lead_fall >= 0))
    throw InvalidArgument("prox-newton: newton_budget must be >= 0, newton_budget_gain finite and >= 1, "
                          "newton_budget_lead_fall >= 0");
  if (d.finish_iterations < 0 || d.safeguard_sweeps < 0 || d.pivot_rows < 0 || d.stale_factor_iterations < 0 ||
      d.body_finish_iterations < 0)
    throw InvalidArgument("prox-newton: finish_iterations, safeguard_sweeps, pivot_rows, stale_factor_iterations and "
                          "body_finish_iterations must be >= 0");
  if (d.continuation_stages < 0 || !(d.continuation_first > 0 && d.continuation_first < 1) ||
      !(d.continuation_within >= 1))
    throw InvalidArgument("prox-newton: continuation_stages must be >= 0, continuation_first in (0, 1) and "
                          "continuation_within >= 1");
  if (d.local_pivot_rows < 0 || d.local_pivot_rings < 0 || d.local_pivot_rounds < 0 || !positive(d.local_pivot_threshold))
    throw InvalidArgument("prox-newton: local_pivot_rows, local_pivot_rings and local_pivot_rounds must be >= 0, "
                          "local_pivot_threshold finite and > 0");
}

}  // namespace dc::solvers::prox
