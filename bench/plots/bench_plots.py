#!/usr/bin/env python3
"""Plots of a `deepcontact bench` run (reads results.h5, writes PNGs next to it).

    python3 bench/plots/bench_plots.py results/results.h5 results/

convergence.png      theta_k vs k: median and quartiles over steps, log-log
sweeps_per_step.png  sweeps until theta <= tol along the trajectory
time_breakdown.png   median ms per step: warm start, sweeps to tol, oracle (apart)
pareto.png           speed/accuracy trade for sweep budgets 1..N (4 panels)
Layout of results.h5: docs/bench.md.
"""
import sys
import os

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


def style(i):
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    return dict(color=cycle[i % len(cycle)])


def convergence(f, names, out, tol, sweeps):
    fig, ax = plt.subplots(figsize=(8, 5.5))
    k = np.arange(1, sweeps + 1)
    for i, n in enumerate(names):
        th = group(f, n)["theta"][()].astype(np.float64)
        th = np.maximum(th, 1e-16)  # exact zeros (converged) drawn at the floor of the log axis
        q1, med, q3 = np.percentile(th, [25, 50, 75], axis=0)
        ax.plot(k, med, label=n, lw=1.5, **style(i))
        ax.fill_between(k, q1, q3, alpha=0.15, **style(i))
    ax.axhline(tol, color="k", ls="--", lw=1, label=f"tol = {tol:g} N")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("PGS sweep k")
    ax.set_ylabel(r"$\theta_k = \max_i |\lambda_i^k - \lambda_i^{k-1}|$  [N]")
    ax.set_title("Convergence (median, shaded: quartiles over steps)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "convergence.png"), dpi=120)
    plt.close(fig)


def sweeps_per_step(f, names, out, sweeps):
    fig, ax = plt.subplots(figsize=(9, 5))
    for i, n in enumerate(names):
        g = group(f, n)
        s = g["sweeps_to_tol"][()].astype(np.float64)
        s[s < 0] = np.nan  # never converged: gap in the line, counted in the table
        x = np.arange(len(s))
        ax.plot(x, s, lw=0.8, label=n, **style(i))
    ax.set_yscale("log")
    ax.set_xlabel("evaluated step (all seeds, in order)")
    ax.set_ylabel("sweeps until θ ≤ tol")
    ax.set_title(f"Sweeps to tolerance per step (gaps: not reached within {sweeps})")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "sweeps_per_step.png"), dpi=120)
    plt.close(fig)


def time_breakdown(f, names, out):
    ws, sv, orc = [], [], []
    paired = f.attrs["mode"] == "paired" if not isinstance(f.attrs["mode"], bytes) else f.attrs["mode"] == b"paired"
    shared_oracle = np.median(f["steps"]["oracle_ms"][()]) if "steps" in f and len(f["steps"]["oracle_ms"]) else 0.0
    for n in names:
        g = group(f, n)
        ws.append(np.median(g["warmstart_ms"][()]))
        sv.append(np.median(g["solve_ms"][()]))
        uses = bool(g.attrs["uses_oracle"])
        own = np.median(g["oracle_ms"][()])
        orc.append((shared_oracle if paired else own) if uses else 0.0)
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
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "time_breakdown.png"), dpi=120)
    plt.close(fig)


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
            ax.plot(t, np.maximum(med, 1e-16), marker=".", ms=4, lw=1.2, label=n, **style(i))
        ax.set_xscale("log")
        if logy:
            ax.set_yscale("log")
        ax.set_xlabel("time per step: warm start + B sweeps [ms]")
        ax.set_ylabel(label + " (median)")
        ax.grid(True, which="both", alpha=0.3)
    axes.flat[0].legend(fontsize=7, ncol=2)
    fig.suptitle(f"Speed/accuracy trade, sweep budgets B = {budgets[0]}…{budgets[-1]}")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "pareto.png"), dpi=110)
    plt.close(fig)


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    f, names = load(sys.argv[1])
    out = sys.argv[2]
    tol = float(f.attrs["tolerance"])
    sweeps = int(f.attrs["sweeps"])
    if len(f["budgets"]) == 0 or len(names) == 0 or group(f, names[0])["theta"].shape[0] == 0:
        print("bench_plots: nothing to plot (no evaluated steps)", file=sys.stderr)
        return 1
    convergence(f, names, out, tol, sweeps)
    sweeps_per_step(f, names, out, sweeps)
    time_breakdown(f, names, out)
    pareto(f, names, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
