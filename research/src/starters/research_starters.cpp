#include "dc/research/research_starters.hpp"

#include "oracle_starters.hpp"

namespace dc {

void add_research_starters(WarmStarterRegistry& r) {
  r.add("copy", "this step's tightly solved lambda* (oracle); copy:D rounds it to D decimals",
        make_copy_warm_starter);
  r.add("copy-noise",
        "oracle with relative Gaussian noise: lambda* x (1 + R xi), xi ~ N(0,1); copy-noise:R (the accuracy a "
        "predictor must reach)",
        make_copy_noise_warm_starter);
  r.add("copy-range",
        "builtin + only the part of lambda* - builtin in the range of A (the velocity-visible part; oracle "
        "diagnostic, dense eigendecomposition, <= 3000 rows)",
        make_copy_range_warm_starter);
  r.add("copy-active",
        "builtin moved least to satisfy the LCP's equations on this step's active set of lambda* (who separates, "
        "sticks, slides), not its values (oracle diagnostic, dense, <= 3000 rows); copy-active:F corrects only a "
        "share F of the contacts where builtin-active's active set is wrong, copy-active:normal|friction only "
        "one half of it",
        make_copy_active_warm_starter);
  r.add("copy-active-cg",
        "copy-active with the solve done matrix-free by ITER CGLS steps (oracle diagnostic, no size limit); "
        "copy-active-cg[:ITER], default 100",
        make_copy_active_cg_warm_starter);
  r.add("sph", "this step's lambda* -> SPH grid -> back at the contacts (oracle grid); sph:KERNEL:D:H[:NORM]",
        make_sph_warm_starter);
  r.add("sph-residual",
        "builtin + the SPH grid read-back of this step's correction lambda* - builtin (oracle bound of a residual "
        "cnn); sph-residual:KERNEL:D:H[:NORM]",
        make_sph_residual_warm_starter);
  r.add("sph-gain",
        "builtin x (1 + the grid's kernel-weighted least-squares gain of this step's correction): oracle bound of "
        "a multiplicative grid correction; sph-gain:KERNEL:D:H",
        make_sph_gain_warm_starter);
  r.add("sph-gain-add",
        "sph-gain + the Shepard read-back of what the gain leaves (new contacts included): oracle; "
        "sph-gain-add:KERNEL:D:H",
        make_sph_gain_add_warm_starter);
  r.add("random",
        "negative control: lambda_n ~ U(0,5)s, lambda_t ~ U(-2,2)s, s = mean weight; random:SEED overrides the "
        "run's seed",
        make_random_warm_starter);
  r.add("bad", "negative control: lambda_n = 50 s (a large constant)", make_bad_warm_starter);
}

}  // namespace dc
