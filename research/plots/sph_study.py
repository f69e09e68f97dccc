#!/usr/bin/env python3
"""Heat maps of a `deepcontact sph-study` run (reads sph_study.csv, writes PNGs).

    python3 research/plots/sph_study.py OUT/sph_study.csv OUT/

One figure per normalisation mode, sph_study_<normalisation>.png: one panel per kernel,
rows = grid spacing d, columns = h/d, colour = median relative round-trip error
|lambda_rt - lambda| / |lambda| on a shared log scale (so the modes can be compared), the
value printed in each cell.
"""
import csv
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.colors import LogNorm
import numpy as np


def main(path, out):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("sph_study.py: empty CSV")

    def ordered(key, conv=str):
        seen = []
        for r in rows:
            v = conv(r[key])
            if v not in seen:
                seen.append(v)
        return seen

    norms = ordered("normalisation")
    kernels = ordered("kernel")
    ds = sorted(ordered("d", float), reverse=True)
    ratios = sorted(ordered("h_over_d", float))
    err = {(r["normalisation"], r["kernel"], float(r["d"]), float(r["h_over_d"])): float(r["median_rel_error"])
           for r in rows}
    finite = [v for v in err.values() if np.isfinite(v) and v > 0]
    vmin = max(min(finite), 1e-16) if finite else 1e-16
    vmax = max(finite) if finite else 1.0
    if vmax <= vmin:
        vmax = vmin * 10

    for norm in norms:
        fig, axes = plt.subplots(1, len(kernels), figsize=(4.2 * len(kernels), 3.8), squeeze=False,
                                 layout="constrained")
        im = None
        for ax, kernel in zip(axes[0], kernels):
            m = np.full((len(ds), len(ratios)), np.nan)
            for i, d in enumerate(ds):
                for j, q in enumerate(ratios):
                    m[i, j] = err.get((norm, kernel, d, q), np.nan)
            shown = np.where(m > 0, m, vmin)  # exact zeros drawn at the floor of the scale
            im = ax.imshow(shown, norm=LogNorm(vmin=vmin, vmax=vmax), cmap="viridis", aspect="auto")
            for i in range(len(ds)):
                for j in range(len(ratios)):
                    v = m[i, j]
                    txt = "n/a" if not np.isfinite(v) else (f"{100 * v:.2g}%" if v >= 1e-4 else f"{v:.0e}")
                    ax.text(j, i, txt, ha="center", va="center", fontsize=7,
                            color="white" if np.isfinite(v) and shown[i, j] < np.sqrt(vmin * vmax) else "black")
            ax.set_xticks(range(len(ratios)), [f"{q:g}" for q in ratios])
            ax.set_yticks(range(len(ds)), [f"{d:g}" for d in ds])
            ax.set_xlabel("h / d")
            if ax is axes[0][0]:
                ax.set_ylabel("d [m]")
            ax.set_title(kernel)
        fig.suptitle(f"SPH round trip, {norm}: median |λ_rt − λ| / |λ|")
        fig.colorbar(im, ax=axes[0].tolist(), shrink=0.9)
        fig.savefig(os.path.join(out, f"sph_study_{norm}.png"), dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
