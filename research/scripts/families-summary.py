#!/usr/bin/python3
"""The per-family table of docs/research.md from one or more bench results.h5 of a family
(paired mode: every starter on the same LCPs; runs on the same scene, seeds and steps are
paired across files too, the bench's trajectory being the oracle's).

Per starter: median sweeps to tolerance (never = cap + 1), unconverged share, the same with
the higher cap (--max-sweeps), the ratio of median sweeps to builtin's, the share of steps on
which the starter needs fewer / more sweeps than builtin, the median initial error
||lambda0 - lambda*||_inf [N], the median residual after 100 sweeps [N], and median
warm-start and total (warm start + solve) ms. Below the table: the median cost of one
sweep [ms] (so a warm start that costs X ms must save X / sweep_ms sweeps to pay).

    /usr/bin/python3 research/scripts/families-summary.py RESULTS.h5 [MORE.h5 ...] [--first-step S]
"""
import json
import os
import sys

import h5py
import numpy as np

args = [a for a in sys.argv[1:] if not a.startswith("--")]
first = 0
if "--first-step" in sys.argv:
    first = int(sys.argv[sys.argv.index("--first-step") + 1])
    args = [a for a in args if a != str(first)]
dec = lambda a: [n.decode() if isinstance(n, bytes) else n for n in a]

ratios = {}  # name -> (median-sweeps ratio, mean-total ratio) to builtin, bootstrap intervals (summary.json)
rows = {}  # name -> dict of per-step arrays (keyed by (seed, step))
order = []
budget_col = None
for path in args:
    f = h5py.File(path, "r")
    sj = os.path.join(os.path.dirname(path), "summary.json")
    if os.path.exists(sj):
        for r in json.load(open(sj))["statistics"]["ratios"]:
            if r["reference"] == "builtin" and r["name"] not in ratios:
                ratios[r["name"]] = (r["median_sweeps_to_tol"], r["mean_total_ms"])
    budgets = list(f["budgets"][:])
    bcol = budgets.index(100) if 100 in budgets else None
    for n, grp in zip(dec(f["warmstarter_names"][:]), dec(f["warmstarter_groups"][:])):
        if n in rows:
            continue
        g = f["warmstarters"][grp]
        cap = int(f.attrs["sweeps"])  # the sweep cap of the run
        sw = g["sweeps_to_tol"][:].astype(float)
        never = sw < 0
        sw[never] = cap + 1
        hi = g["sweeps_to_tol_high"][:].astype(float) if "sweeps_to_tol_high" in g else None
        hcap = int(g.attrs["max_sweeps"]) if hi is not None else None
        if hi is not None:
            hnever = hi < 0
            hi[hnever] = hcap + 1
        keep = g["step"][:] >= first
        key = list(zip(g["seed"][:][keep], g["step"][:][keep]))
        rows[n] = dict(key=key, sw=sw[keep], never=never[keep], cap=cap,
                       hi=None if hi is None else hi[keep], hnever=None if hi is None else hnever[keep], hcap=hcap,
                       err=g["initial_error"][:][keep],
                       res=g["residual"][:, bcol][keep] if bcol is not None else None,
                       ws=g["warmstart_ms"][:][keep], tot=(g["warmstart_ms"][:] + g["solve_ms"][:])[keep],
                       sweep_ms=g["sweep_ms"][:][keep], oracle=int(g.attrs["uses_oracle"]))
        order.append(n)

base = rows.get("builtin")
def paired(r):
    if base is None or r["key"] != base["key"]:
        return float("nan"), float("nan")
    return 100 * np.mean(r["sw"] < base["sw"]), 100 * np.mean(r["sw"] > base["sw"])

r0 = rows[order[0]]
hc = r0["hcap"] if r0["hcap"] is not None else "—"
print("steps per starter: %d (seeds %s; steps >= %d)" % (len(r0["key"]), sorted({int(k[0]) for k in r0["key"]}), first))
hdr = ("| starter | median sweeps | never (%d) | median sweeps, cap %s | never (%s) | / builtin [95 %%] | fewer / more than builtin "
       "| median λ⁰ err [N] | resid@100 [N] | warm-start ms | total ms | mean total / builtin [95 %%] |" % (r0["cap"], hc, hc))
print(hdr)
print("|---|" + "---:|" * (hdr.count("|") - 2))
for n in order:
    r = rows[n]
    med = np.median(r["sw"])
    ratio = med / np.median(base["sw"]) if base is not None else float("nan")
    fewer, more = paired(r)
    cap_s = lambda m, c: "never" if m > c else "%.0f" % m
    hi = "—" if r["hi"] is None else cap_s(np.median(r["hi"]), r["hcap"])
    hn = "—" if r["hi"] is None else "%.1f %%" % (100 * r["hnever"].mean())
    iv = lambda x: "%.2f [%.2f, %.2f]" % (x["estimate"], x["lo"], x["hi"])
    rs = iv(ratios[n][0]) if n in ratios else "%.2f" % ratio
    rt = iv(ratios[n][1]) if n in ratios else ("1" if n == "builtin" else "—")
    print("| %s%s | %s | %.1f %% | %s | %s | %s | %.0f / %.0f %% | %.3g | %s | %.3f | %.2f | %s |" % (
        n, " *" if r["oracle"] else "", cap_s(med, r["cap"]), 100 * r["never"].mean(), hi, hn, rs, fewer, more,
        np.median(r["err"]), "—" if r["res"] is None else "%.2g" % np.median(r["res"]), np.median(r["ws"]),
        np.median(r["tot"]), rt))
print("\n`*` = oracle starter (uses this step's λ*). Median cost of one PGS sweep: %.4f ms (builtin's steps)."
      % np.median((base or r0)["sweep_ms"]))
