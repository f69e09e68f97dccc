#include "starters.hpp"

namespace dc {

// Only methods: no starter here reads this step's solution (uses_oracle() is false) and none is
// a negative control; dc_research adds those (add_research_starters).
WarmStarterRegistry default_warm_starters() {
  WarmStarterRegistry r;
  r.add("zero", "lambda0 = 0 (baseline)", make_zero_warm_starter);
  r.add("builtin", "previous step's lambda of the contact with the same key, 0 if new",
        make_builtin_warm_starter);
  r.add("builtin-extrapolate",
        "builtin with linear extrapolation 2 lambda(t-1) - lambda(t-2) of contacts seen in both steps, clamped to "
        "the cone",
        make_extrapolate_warm_starter);
  r.add("builtin-gain-extrapolate",
        "builtin x (1 + the grid-smoothed gain of the load change from step t-2 to t-1): a smoothed temporal "
        "extrapolation; builtin-gain-extrapolate:KERNEL:D:H",
        make_gain_extrapolate_warm_starter);
  r.add("builtin-statics",
        "builtin, plus a statics guess for new contacts: each body's weight and the load on it pushed down to its "
        "supports",
        make_statics_warm_starter);
  r.add("builtin-coarse",
        "builtin + a Galerkin coarse-grid correction: the gain field on a grid of spacing D that minimises the "
        "contact energy, by ITER conjugate-gradient steps (no oracle); builtin-coarse[:D[:ITER]], default 1:30",
        make_coarse_warm_starter);
  r.add("builtin-active",
        "builtin moved least to satisfy the LCP's equations on builtin's remembered active set (who separates, "
        "sticks, slides; new closing contacts stick); dense, <= 3000 rows",
        make_builtin_active_warm_starter);
  r.add("builtin-active-cg",
        "builtin-active with the solve done matrix-free by ITER CGLS steps (no size limit); "
        "builtin-active-cg[:ITER], default 100",
        make_builtin_active_cg_warm_starter);
  r.add("sph-prev", "previous step's lambda -> SPH grid -> this step's contacts; sph-prev:KERNEL:D:H[:NORM]",
        make_sph_prev_warm_starter);
  r.add("gate",
        "safeguard: per step, INNER's guess or builtin's, whichever has the smaller natural-map residual "
        "(max norm); gate:INNER, e.g. gate:cnn:models/impact.h5",
        make_gate_warm_starter);
  r.add("gate-l2", "gate with the residual's 2-norm instead of its max norm; gate-l2:INNER",
        make_gate_warm_starter);
  return r;
}

}  // namespace dc
