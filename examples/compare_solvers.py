#!/usr/bin/env python3
"""Every LCP solver on one contact problem of the seed scene (step 300 of seed 1).

    PYTHONPATH=build/python /usr/bin/python3 examples/compare_solvers.py [--plot theta.png]
"""
import argparse

import numpy as np

import deepcontact as dc

ap = argparse.ArgumentParser()
ap.add_argument("--plot", help="write θ_k of the iterative solvers to this PNG")
args = ap.parse_args()

world = dc.World()  # the seed scene: 100 circles in a 30 × 30 box
for _ in range(300):
    world.step(sweeps=300, tol=1e-4)
world.collide()
problem = world.assemble()
print(f"step 300: {len(world.contacts.gap)} contacts, {problem.rows} rows, A with {problem.A.nnz} non-zeros")

exact = dc.solve(problem, "newton")
print(f"{'solver':14} {'status':11} {'sweeps':>6} {'residual [N]':>13} {'|λ − λ_newton|∞':>16}")
curves = {}
for name in dc.solvers():
    r = dc.solve(problem, name, sweeps=3000, tol=1e-6)
    err = np.max(np.abs(r.lam - exact.lam)) if len(r.lam) else 0.0
    print(f"{name:14} {r.status:11} {r.sweeps:6d} {r.residual:13.3e} {err:16.3e}")
    if len(r.theta):
        curves[name] = np.asarray(r.theta)

if args.plot:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for name, theta in curves.items():
        ax.semilogy(np.arange(1, len(theta) + 1), theta, label=name)
    ax.set_xlabel("sweep k")
    ax.set_ylabel("θ_k = max |λ^k − λ^(k−1)| [N]")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.plot, dpi=120)
    print(f"wrote {args.plot}")
