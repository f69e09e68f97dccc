#!/usr/bin/env python3
"""Size-sweep plot of `deepcontact bench --scale`: per starter against the body count N,
median sweeps to tol (and with the higher cap), median residual at the fixed budget and
median total time per step. Usage: scale_plot.py scale.csv scale.png"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(src, dst):
    rows = list(csv.DictReader(open(src)))
    starters = []
    for r in rows:
        if r["starter"] not in starters:
            starters.append(r["starter"])
    has_high = any(int(r["max_sweeps"]) > 0 for r in rows)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    for s in starters:
        rs = sorted((r for r in rows if r["starter"] == s), key=lambda r: int(r["bodies"]))
        n = [int(r["bodies"]) for r in rs]
        line, = ax[0].plot(n, [float(r["median_sweeps_to_tol"]) for r in rs], "o-", label=s)
        if has_high:
            ax[0].plot(n, [float(r["median_sweeps_high_cap"]) for r in rs], "s--", color=line.get_color(),
                       alpha=0.6)
        ax[1].plot(n, [max(float(r["residual_at_budget"]), 1e-16) for r in rs], "o-", label=s)
        ax[2].plot(n, [float(r["total_ms"]) for r in rs], "o-", label=s)
    cap = int(rows[0]["sweeps"]) if rows else 0
    ax[0].axhline(cap, color="grey", lw=0.8, ls=":")
    ax[0].set_title("median sweeps to tol" + (" (dashed: higher cap)" if has_high else "") + f"; cap {cap} dotted")
    ax[1].set_title(f"median residual after {rows[0]['budget'] if rows else '?'} sweeps [N]")
    ax[2].set_title("median total ms per step (warm start + solve)")
    for a in ax:
        a.set_xlabel("bodies N")
        a.set_xscale("log")
        a.set_yscale("log")
        a.grid(True, which="both", alpha=0.3)
    ax[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(dst, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
