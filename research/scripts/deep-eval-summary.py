#!/usr/bin/python3
"""Per-starter summary of a bench results.h5 (docs/research/deep-pile.md): median sweeps to
tolerance over all steps and over the settled steps (step >= SETTLED), the never-converged
share, the median initial error ||lambda0 - lambda*||_inf, the median residual at fixed
budgets, and median warm-start / total ms.

    /usr/bin/python3 research/scripts/deep-eval-summary.py build/data/deep-bench/results.h5 [SETTLED=150]
"""
import sys

import h5py
import numpy as np

path = sys.argv[1]
settled = int(sys.argv[2]) if len(sys.argv) > 2 else 150
f = h5py.File(path, "r")
budgets = f["budgets"][:]
dec = lambda a: [n.decode() if isinstance(n, bytes) else n for n in a]
names = dec(f["warmstarter_names"][:])
groups = dict(zip(names, dec(f["warmstarter_groups"][:])))
pick = [b for b in (10, 100, 1000, 3000) if b in budgets]
hdr = ("| starter | median sweeps (all) | median sweeps (steps >= %d) | never (all) | never (settled) | "
       "median init err [N] | " % settled + " | ".join("resid@%d [N]" % b for b in pick) +
       " | warm start ms | total ms |")
print(hdr)
print("|" + "---|" * (hdr.count("|") - 1))
for n in names:
    g = f["warmstarters"][groups[n]]
    sw = g["sweeps_to_tol"][:].astype(float)
    step = g["step"][:]
    cap = int(f.attrs["sweeps"])  # the sweep cap of the run
    never = sw < 0  # never converged within the cap: counted as cap + 1 (as the bench does)
    sw[never] = cap + 1
    s = step >= settled
    res = g["residual"][:]
    col = [np.median(res[:, list(budgets).index(b)]) for b in pick]
    tot = g["solve_ms"][:] + g["warmstart_ms"][:]
    print("| %s | %.0f | %.0f | %.1f %% | %.1f %% | %.3g | %s | %.3f | %.3f |" % (
        n, np.median(sw), np.median(sw[s]) if s.any() else float("nan"), 100 * never.mean(),
        100 * never[s].mean() if s.any() else float("nan"), np.median(g["initial_error"][:]),
        " | ".join("%.3g" % c for c in col), np.median(g["warmstart_ms"][:]), np.median(tot)))
