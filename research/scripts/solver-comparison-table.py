#!/usr/bin/env python3
"""The "Solver × warm start" table from the reports of research/scripts/solver-comparison.sh
(OUT/<family>/results.h5 and summary.json), printed; `make results PART=solvers`
(scripts/results/parts.py) calls table() and writes it into docs/results/solvers.md.

    research/scripts/solver-comparison-table.py OUT

Per family and for pgs+builtin, nncg+builtin and newton-sparse+{zero, builtin, cnn, copy}: the
share of steps reaching the accuracy target R, median ms to R, median iterations to R and median
total ms (warm start + solve to θ ≤ tol), each with its bootstrap 95 % interval, and the ratios
of median ms to R and of median total ms to pgs+builtin's median total ms (results.h5
/solvers/intervals, docs/bench.md).
"""
import json
import os
import sys

import h5py

FAMILIES = ["seed", "impact", "impact_1000", "deep", "pour", "drum", "polydisperse", "box_pile"]
PAIRS = [("pgs", "builtin"), ("nncg", "builtin"), ("newton-sparse", "zero"), ("newton-sparse", "builtin"),
         ("newton-sparse", "cnn"), ("newton-sparse", "copy")]


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def load(out, family):
    """{(solver, starter): {figure: (est, lo, hi)}} and the run's facts, or None."""
    h5 = os.path.join(out, family, "results.h5")
    if not os.path.exists(h5):
        return None
    with h5py.File(h5, "r") as f:
        if "solvers" not in f:
            return None
        s = f["solvers"]
        figures = [text(x) for x in s["interval_figures"][()]]
        iv = s["intervals"][()]
        pairs = {}
        for i, g in enumerate(text(x) for x in s["pair_groups"][()]):
            key = (text(s[g].attrs["solver"]), text(s[g].attrs["starter"]))
            pairs[key] = {fig: tuple(iv[i, j]) for j, fig in enumerate(figures)}
            pairs[key]["steps"] = len(s[g]["seed"])
        facts = {"accuracy": float(s.attrs["accuracy"]), "cap": int(s.attrs["cap"]), "machine": text(f.attrs["machine"]),
                 "seeds": list(f.attrs["seeds"]), "tolerance": float(f.attrs["tolerance"])}
    with open(os.path.join(out, family, "summary.json")) as fh:
        facts["wall_seconds"] = json.load(fh)["wall_seconds"]
    load_file = os.path.join(out, family + ".load")
    facts["load"] = open(load_file).read().split("load average:")[-1].split("\n")[0].strip() if os.path.exists(load_file) else "?"
    return pairs, facts


def fmt(x, spec):
    est, lo, hi = x
    if est != est:  # NaN
        return "–"
    return f"{est:{spec}} [{lo:{spec}}, {hi:{spec}}]"


def table(out):
    rows, notes = [], []
    head = ("| family | solver + start | reached R | ms to R | iterations to R | total ms | ms to R / pgs+builtin total "
            "| total / pgs+builtin total |\n|---|---|---:|---:|---:|---:|---:|---:|")
    for fam in FAMILIES:
        got = load(out, fam)
        if got is None:
            notes.append(f"{fam}: not run")
            continue
        pairs, facts = got
        for solver, starter in PAIRS:
            x = pairs.get((solver, starter))
            if x is None:
                continue
            rows.append(f"| {fam} | {solver} + {starter} | {fmt(x['reached_share'], '.2f')} | "
                        f"{fmt(x['median_ms_to_accuracy'], '.3g')} | {fmt(x['median_iterations_to_accuracy'], '.0f')} | "
                        f"{fmt(x['median_total_ms'], '.3g')} | {fmt(x['ms_to_accuracy_over_pgs_builtin_total'], '.3g')} | "
                        f"{fmt(x['total_over_pgs_builtin_total'], '.3g')} |")
        steps = max(v["steps"] for v in pairs.values())
        notes.append(f"{fam}: {steps} steps, seeds {','.join(map(str, facts['seeds']))}, wall {facts['wall_seconds']:.0f} s, "
                     f"load {facts['load']}")
    return head + "\n" + "\n".join(rows), notes


def machine(out):
    """machine.txt (lscpu model line, nproc, uptime, date) as one phrase."""
    path = os.path.join(out, "machine.txt")
    if not os.path.exists(path):
        return "?"
    lines = open(path).read().splitlines()
    model = lines[0].split(":", 1)[-1].strip() if lines else "?"
    cores = lines[1].strip() if len(lines) > 1 else "?"
    load = lines[2].split("load average:")[-1].strip() if len(lines) > 2 else "?"
    date = lines[3].strip() if len(lines) > 3 else "?"
    return f"{model}, {cores} cores shared with other jobs, load average {load} at the start ({date})"


def headline(out):
    """Per family the non-oracle pair with the least median ms to R among those reaching R on every
    step (else the highest share), against pgs+builtin's median total ms."""
    parts = []
    for fam in FAMILIES:
        got = load(out, fam)
        if got is None:
            continue
        pairs = got[0]
        cands = [(k, v) for k, v in pairs.items() if k in PAIRS and k[1] != "copy"]
        if not cands or ("pgs", "builtin") not in pairs:
            continue
        best = min(cands, key=lambda kv: (-kv[1]["reached_share"][0], kv[1]["median_ms_to_accuracy"][0]))
        (solver, starter), v = best
        parts.append(f"{fam} {solver}+{starter} {v['median_ms_to_accuracy'][0]:.3g} ms "
                     f"(reached {v['reached_share'][0]:.0%}; pgs+builtin total {pairs[('pgs', 'builtin')]['median_total_ms'][0]:.3g} ms)")
    return "; ".join(parts)


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    out = sys.argv[1]
    tab, notes = table(out)
    print(f"Machine: {machine(out)}. Runs: " + "; ".join(notes) + ".\n\n" + tab)
    print("\nFastest to R = 1e-6 per family among the pairs reaching it on the most steps: " + headline(out) + ".")
    return 0


if __name__ == "__main__":
    sys.exit(main())
