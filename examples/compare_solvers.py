#!/usr/bin/env python3
"""Every LCP solver on one contact problem of the seed scene (step 300 of seed 1), with what
each status means.

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

# What each status means (docs/lcp.md); every non-converged row also prints the solver's own message.
MEANING = {
    "converged": "the returned λ passes the solution test (natural residual ≤ 1e-9·‖b‖∞)",
    "tolerance_reached": "stopped at θ ≤ tol, but the returned λ does not pass the solution test: no solution claimed",
    "sweep_limit": "ran every sweep without reaching the tolerance (slow convergence, the last iterate is returned)",
    "diverged": "the iterates grew without bound (undamped jacobi on a pile: pass omega < 1 as damping)",
    "failed": "the method broke down (singular pivot, stalled line search, …; see its message)",
    "invalid_input": "the problem is outside what the method solves (lemke: a standard LCP λ ≥ 0, no friction rows)",
    "infeasible": "proved to have no solution",
}

results = {name: dc.solve(problem, name, sweeps=3000, tol=1e-6) for name in dc.solvers()}
# The reference: the λ with the smallest natural-map residual, whichever solver returned it
# (a pile's λ need not be unique, so the distance to it is a guide, not an error).
solved = {n: r for n, r in results.items() if len(r.lam) and np.isfinite(r.residual)}
ref_name = min(solved, key=lambda n: solved[n].residual) if solved else None
print(f"reference λ: {ref_name}'s (the smallest residual)")
print(f"{'solver':14} {'status':17} {'sweeps':>6} {'residual [N]':>13} {'|λ − λ_ref|∞':>14}")
curves = {}
for name, r in results.items():
    err = np.max(np.abs(r.lam - solved[ref_name].lam)) if ref_name and len(r.lam) else float("nan")
    print(f"{name:14} {r.status:17} {r.sweeps:6d} {r.residual:13.3e} {err:14.3e}")
    if len(r.theta):
        curves[name] = np.asarray(r.theta)
print()
for status in sorted({r.status for r in results.values()} - {"converged"}):
    print(f"{status}: {MEANING.get(status, 'see docs/lcp.md')}")
    for name, r in results.items():
        if r.status == status and r.message:
            print(f"    {name}: {r.message}")

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
