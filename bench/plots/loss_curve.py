#!/usr/bin/env python3
"""Loss curve of a `deepcontact train` run (reads OUT.loss.csv, writes a PNG).

    python3 bench/plots/loss_curve.py OUT.loss.csv OUT.loss.png

Training and validation loss (MSE in standardised label units; weighted when the run used
--contact-weight) against the epoch, log scale; the best validation epoch is marked.
"""
import csv
import math
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main(path, out):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("loss_curve.py: empty CSV")
    epoch = [int(r["epoch"]) for r in rows]
    train = [float(r["train_loss"]) for r in rows]
    val = [float(r["validation_loss"]) for r in rows]
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(epoch, train, marker=".", label="train")
    if not all(math.isnan(v) for v in val):
        ax.plot(epoch, val, marker=".", label="validation")
        finite = [(v, e) for v, e in zip(val, epoch) if not math.isnan(v)]
        best_v, best_e = min(finite)
        ax.plot([best_e], [best_v], "k*", markersize=10, label=f"best: epoch {best_e}, {best_v:.4g}")
    ax.set_yscale("log")
    ax.set_xlabel("epoch")
    ax.set_ylabel("MSE (standardised labels)")
    ax.set_title("deepcontact train")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: loss_curve.py OUT.loss.csv OUT.loss.png")
    main(sys.argv[1], sys.argv[2])
