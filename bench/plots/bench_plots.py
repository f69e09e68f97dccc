#!/usr/bin/env python3
"""Plots of a `deepcontact bench` run (reads results.h5, writes PNGs next to it).

    python3 bench/plots/bench_plots.py results/results.h5 results/

intervals.png        median sweeps to tol and total ms with bootstrap 95 % intervals, per-seed medians
convergence.png      theta_k vs k: median (quartile bands for <= 6 starters) over steps, log-log
sweeps_per_step.png  sweeps until theta <= tol along the trajectory (running median)
time_breakdown.png   median ms per step: warm start, sweeps to tol, oracle (apart)
pareto.png           speed/accuracy trade for sweep budgets 1..N (4 panels)
accuracy.png         with --solvers: median accuracy against time per step, one curve per (solver, starter)

A plot that does not apply to the run is not drawn: NAME.na holds one line saying why. A
plot that fails prints its traceback, the others are still drawn, and the exit status is 1.
Layout of results.h5: docs/bench.md.
"""
import sys
import os
import traceback

import h5py
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np


def load(path):
    f = h5py.File(path, "r")
    order = [n.decode() if isinstance(n, bytes) else str(n) for n in f["warmstarter_names"][()]]
    return f, order


def group(f, name):
    """The /warmstarters group of a starter: its name with '%' -> %25 and '/' -> %2F."""
    return f["warmstarters"][name.replace("%", "%25").replace("/", "%2F")]


# Sixteen distinct colours (tab10 and six more) × four dash patterns: the first sixteen
# starters differ in colour, neighbours in the table also in dash, and (colour, dash) pairs
# stay distinct up to 64 starters.
COLOURS = list(plt.get_cmap("tab10").colors) + ["black", "navy", "#e7298a", "#b8860b", "#66a61e", "teal"]
DASHES = ["-", "--", "-.", ":"]
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*"]


def style(i):
    return dict(color=COLOURS[i % len(COLOURS)], ls=DASHES[(i + i // len(COLOURS)) % len(DASHES)])


def legend_outside(ax, n):
    """The legend right of the axes, so it never covers data (one column up to 14 names)."""
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0,
              ncol=1 if n <= 14 else 2, frameon=False)


def text_attr(f, key):
    v = f.attrs[key]
    return v.decode() if isinstance(v, bytes) else str(v)


def save(fig, out, name, dpi=120):
    fig.savefig(os.path.join(out, name), dpi=dpi, bbox_inches="tight")
    plt.close(fig)


def theta_quartiles(g):
    """Quartiles of θ_k over the steps, per sweep: from /theta_quartiles (always written), or
    from the full per-step /theta of a `--theta` run or an older file. Exact zeros (converged)
    are drawn at the floor of the log axis."""
    if "theta_quartiles" in g:
        q = np.maximum(g["theta_quartiles"][()], 1e-16)
        return q[:, 0], q[:, 1], q[:, 2]
    th = np.maximum(g["theta"][()].astype(np.float64), 1e-16)
    return tuple(np.percentile(th, [25, 50, 75], axis=0))


def convergence(f, names, out, tol, sweeps):
    fig, ax = plt.subplots(figsize=(8, 5.5))
    k = np.arange(1, sweeps + 1)
    bands = len(names) <= 6
    for i, n in enumerate(names):
        q1, med, q3 = theta_quartiles(group(f, n))
        ax.plot(k, med, label=n, lw=1.5, **style(i))
        if bands:  # a dozen overlapping bands hide every line: only for a few starters
            ax.fill_between(k, q1, q3, alpha=0.12, color=style(i)["color"], lw=0)
    ax.axhline(tol, color="k", ls="--", lw=1, label=f"tol = {tol:g} N")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("PGS sweep k")
    ax.set_ylabel(r"$\theta_k = \max_i |\lambda_i^k - \lambda_i^{k-1}|$  [N]")
    ax.set_title("Convergence (median" + (", shaded: quartiles" if bands else "") + " over steps)")
    ax.grid(True, which="both", alpha=0.3)
    legend_outside(ax, len(names) + 1)
    save(fig, out, "convergence.png")


def running_median(v, w):
    """Median over a centred window of w points (shorter at the ends)."""
    h = w // 2
    return np.array([np.median(v[max(0, i - h):i + h + 1]) for i in range(len(v))])


def sweeps_per_step(f, names, out, sweeps, window=15):
    fig, ax = plt.subplots(figsize=(11, 5))
    seeds = [int(s) for s in f.attrs["seeds"]]
    # The seeds one after another, each over the steps it ran (after --warmup-steps): x = seed
    # index · span + step − first. Starting each seed at step 0 instead left the warm-up as an
    # empty band, and a label placed there stretched the tight bounding box of a short run to
    # a figure too wide to draw (a 2-step window after 195 warm-up steps: 180 000 px).
    steps = [group(f, n)["step"][()] for n in names if len(group(f, n)["step"])]
    first = min((int(np.min(st)) for st in steps), default=0)
    span = 1 + max((int(np.max(st)) for st in steps), default=0) - first
    for i, n in enumerate(names):
        g = group(f, n)
        s = g["sweeps_to_tol"][()].astype(np.float64)
        s[s < 0] = sweeps + 1  # never converged: counted as sweeps + 1, as in the table
        seed = g["seed"][()]
        x = np.array([seeds.index(int(a)) for a in seed]) * span + g["step"][()] - first
        for j, sd in enumerate(seeds):  # one line per seed: the running median never spans two
            m = seed == sd
            if m.any():
                ax.plot(x[m], running_median(s[m], window), lw=1.1, label=n if j == 0 else None,
                        marker=MARKERS[i % len(MARKERS)], markevery=max(1, int(m.sum()) // 6), ms=4, **style(i))
    for j, sd in enumerate(seeds):
        if j:
            ax.axvline(j * span, color="gray", lw=0.6, ls=":")
        ax.text(j * span + 0.01 * span, 1.02, f"seed {sd}", transform=ax.get_xaxis_transform(), fontsize=7)
    ax.axhline(sweeps + 1, color="k", lw=0.6, ls=":")
    ax.set_yscale("log")
    ax.set_xlabel("step" + (f" − {first}" if first else "") + " (the seeds one after another)")
    ax.set_ylabel(f"sweeps until θ ≤ tol (running median of {window})")
    ax.grid(True, which="major", alpha=0.3)
    ax.set_title(f"Sweeps to tolerance per step (dotted line at {sweeps + 1}: not reached within {sweeps})",
                 pad=14)
    legend_outside(ax, len(names))
    save(fig, out, "sweeps_per_step.png")


def time_breakdown(f, names, out):
    ws, sv, orc = [], [], []
    paired = text_attr(f, "mode") == "paired"
    # The shared oracle exists in paired mode only (rollout: each oracle starter solves its own).
    has_shared = "steps" in f and "oracle_ms" in f["steps"] and len(f["steps"]["oracle_ms"]) > 0
    shared_oracle = float(np.median(f["steps"]["oracle_ms"][()])) if has_shared else 0.0
    for n in names:
        g = group(f, n)
        ws.append(np.median(g["warmstart_ms"][()]))
        sv.append(np.median(g["solve_ms"][()]))
        uses = bool(g.attrs["uses_oracle"])
        own = np.median(g["oracle_ms"][()])
        orc.append((shared_oracle if paired and has_shared else own) if uses else 0.0)
    y = np.arange(len(names))
    fig, ax = plt.subplots(figsize=(8, 0.5 * len(names) + 1.8))
    ax.barh(y, ws, label="warm start", color="tab:orange")
    ax.barh(y, sv, left=ws, label="PGS sweeps until tol", color="tab:blue")
    # The oracle (tens of ms) is not part of any total: a bar would set the axis scale and
    # squash the totals that matter, so it is written next to the bar instead.
    totals = np.array(ws) + np.array(sv)
    right = max(float(totals.max()) if len(totals) else 1.0, 1e-6)
    for yi, (t, o) in enumerate(zip(totals, orc)):
        if o > 0:
            ax.text(t + 0.01 * right, yi, f"+ oracle λ* {o:.1f} ms (apart)", va="center", fontsize=7, color="dimgray")
    ax.set_xlim(0, right * 1.45)
    ax.set_yticks(y)
    ax.set_yticklabels(names)
    ax.invert_yaxis()
    ax.set_xlabel("median time per step [ms]")
    ax.set_title("Contact-solution time per step")
    ax.grid(True, axis="x", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    save(fig, out, "time_breakdown.png")


def pareto(f, names, out):
    budgets = f["budgets"][()]
    panels = [("residual", "natural-map residual [N]", True),
              ("lambda_error", r"$\|\lambda_B - \lambda^*\|_\infty$ [N]", True),
              ("penetration", "max penetration after step [m]", True),
              ("energy_error", r"$|E(\lambda_B) - E(\lambda^*)|$ after step [J]", True)]
    fig, axes = plt.subplots(2, 2, figsize=(12, 9))
    for ax, (key, label, logy) in zip(axes.flat, panels):
        for i, n in enumerate(names):
            g = group(f, n)
            v = g[key][()]
            if key == "energy_error":
                v = np.abs(v)
            med = np.median(v, axis=0)
            t = np.median(g["warmstart_ms"][()]) + budgets * np.median(g["sweep_ms"][()])
            ax.plot(t, np.maximum(med, 1e-16), marker=MARKERS[i % len(MARKERS)], ms=3, lw=1.2, label=n, **style(i))
        ax.set_xscale("log")
        if logy:
            ax.set_yscale("log")
        ax.set_xlabel("time per step: warm start + B sweeps [ms]")
        ax.set_ylabel(label + " (median)")
        ax.grid(True, which="both", alpha=0.3)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.suptitle(f"Speed/accuracy trade, sweep budgets B = {budgets[0]}…{budgets[-1]}")
    fig.tight_layout(rect=(0, 0, 0.85, 1))
    fig.legend(handles, labels, fontsize=8, loc="upper left", bbox_to_anchor=(0.86, 0.95), frameon=False)
    save(fig, out, "pareto.png", dpi=110)


def intervals(f, names, out):
    st = f["statistics"]
    order = [n.decode() if isinstance(n, bytes) else str(n) for n in st["starters"][()]]
    never = int(st.attrs["never_counts_as"])
    seeds = [int(x) for x in st["seeds"][()]]
    fig, axes = plt.subplots(1, 2, figsize=(12, 0.42 * len(order) + 2.2), sharey=True)
    panels = [(axes[0], "median_sweeps_to_tol", "seed_median_sweeps_to_tol", "median sweeps to tol"),
              (axes[1], "median_total_ms", "seed_median_total_ms", "median total ms per step (warm start + solve)")]
    y = np.arange(len(order))
    for ax, key, seed_key, label in panels:
        est = st[key][()]
        per_seed = st[seed_key][()] if seed_key in st else np.empty((len(order), 0))
        for i in range(len(order)):
            c = style(i)["color"]
            ax.scatter(per_seed[i], np.full(per_seed.shape[1], y[i]) + 0.18, s=9, color=c, alpha=0.6, lw=0)
            lo, hi = est[i, 1], est[i, 2]
            ax.errorbar([est[i, 0]], [y[i]], xerr=[[est[i, 0] - lo], [hi - est[i, 0]]], fmt="o", ms=4, color=c,
                        capsize=3, lw=1.4)
        if key.endswith("sweeps_to_tol"):
            ax.axvline(never, color="k", lw=0.6, ls=":")
        ax.set_xscale("log")
        ax.set_xlabel(label)
        ax.grid(True, which="both", axis="x", alpha=0.3)
    axes[0].set_yticks(y)
    axes[0].set_yticklabels(order)
    axes[0].invert_yaxis()
    paired = bool(st.attrs["paired"])
    fig.suptitle(f"Medians with bootstrap {100 * float(st.attrs['level']):.0f} % intervals "
                 f"({int(st.attrs['resamples'])} {'paired ' if paired else ''}hierarchical resamples; "
                 f"dots: seeds {', '.join(map(str, seeds))})", fontsize=10)
    fig.tight_layout()
    save(fig, out, "intervals.png")


def accuracy(f, out):
    """Median accuracy (residual / heaviest weight) against time per step, one curve per pair.

    A step's accuracy at time t is that of its last traced point at or before t (its λ⁰ at the
    warm start's end; before that it has no λ and counts as infinitely inaccurate, so a curve
    starts once half the steps have a λ); after reaching the target its trace ends and it counts
    at its last value."""
    s = f["solvers"]
    target = float(s.attrs["accuracy"])
    names = [n.decode() if isinstance(n, bytes) else str(n) for n in s["pair_names"][()]]
    groups = [n.decode() if isinstance(n, bytes) else str(n) for n in s["pair_groups"][()]]
    traces = []
    t_min, t_max = np.inf, 0.0
    for g in groups:
        off = s[g]["trace_offsets"][()]
        ms = s[g]["trace_ms"][()]
        acc = s[g]["trace_accuracy"][()]
        steps = [(ms[off[k]:off[k + 1]], acc[off[k]:off[k + 1]]) for k in range(len(off) - 1)]
        traces.append(steps)
        for t, _ in steps:
            if len(t):
                t_min, t_max = min(t_min, max(t[0], 1e-4)), max(t_max, t[-1])
    if not np.isfinite(t_min) or t_max <= 0:
        raise ValueError("no traced points")
    grid = np.logspace(np.log10(t_min), np.log10(max(t_max, 1.0001 * t_min)), 200)
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for i, (name, steps) in enumerate(zip(names, traces)):
        values = np.full((len(steps), grid.size), np.inf)
        for k, (t, a) in enumerate(steps):
            if len(t) == 0:
                continue
            idx = np.searchsorted(t, grid, side="right") - 1
            ok = idx >= 0
            values[k, ok] = a[idx[ok]]
        med = np.median(values, axis=0) if len(steps) else np.full(grid.size, np.inf)
        med[~np.isfinite(med)] = np.nan  # not drawn: fewer than half the steps have a λ yet
        ax.plot(grid, np.maximum(med, 1e-16), label=name, lw=1.5, **style(i))
    ax.axhline(target, color="k", ls=":", lw=1, label=f"target R = {target:g}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time per step (warm start + solve) [ms]")
    ax.set_ylabel("median natural-map residual / max m g")
    ax.grid(True, which="both", alpha=0.3)
    legend_outside(ax, len(names) + 1)
    save(fig, out, "accuracy.png")


def not_applicable(out, png, why):
    with open(os.path.join(out, png[:-4] + ".na"), "w") as fh:
        fh.write(why + "\n")


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    f, names = load(sys.argv[1])
    out = sys.argv[2]
    tol = float(f.attrs["tolerance"])
    sweeps = int(f.attrs["sweeps"])
    plots = [("intervals.png", lambda: intervals(f, names, out)),
             ("convergence.png", lambda: convergence(f, names, out, tol, sweeps)),
             ("sweeps_per_step.png", lambda: sweeps_per_step(f, names, out, sweeps)),
             ("time_breakdown.png", lambda: time_breakdown(f, names, out)),
             ("pareto.png", lambda: pareto(f, names, out))]
    if "solvers" in f:
        plots.append(("accuracy.png", lambda: accuracy(f, out)))
    empty = len(names) == 0 or all(group(f, n)["sweeps_to_tol"].shape[0] == 0 for n in names)
    failed = []
    for png, draw in plots:
        if empty:
            not_applicable(out, png, "no evaluated steps (no step had a contact)")
            continue
        if png == "intervals.png" and "statistics" not in f:
            not_applicable(out, png, "results.h5 has no /statistics group")
            continue
        try:
            draw()
        except Exception:  # one failed plot must not cost the others
            print(f"bench_plots: {png} failed:", file=sys.stderr)
            traceback.print_exc()
            failed.append(png)
    if failed:
        print("bench_plots: failed: " + ", ".join(failed), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
