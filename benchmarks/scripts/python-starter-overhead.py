#!/usr/bin/env python3
"""The per-call overhead of a warm starter written in Python (docs/python.md).

    PYTHONPATH=build/python /usr/bin/python3 benchmarks/scripts/python-starter-overhead.py [--steps 200] [--seeds 1]

Runs one paired bench with the C++ starters zero and builtin and their Python
re-implementations (py-zero: np.zeros; py-builtin: previous λ by key in a dict), and prints
the median warm-start time per step of each (the bench times initial_guess() itself: for a
Python starter that includes taking the GIL, building the view, the Python call and the
conversion of its result). Also times the bare call path (a starter that returns a cached
array) and CPU time of the whole run. Timings are the machine's: compare side by side.
"""
import argparse
import resource
import time

import numpy as np

import deepcontact as dc


class PyZero(dc.WarmStarter):
    def name(self):
        return "py-zero"

    def initial_guess(self, view):
        return np.zeros(view.rows)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--seeds", default="1")
    ap.add_argument("--sweeps", type=int, default=300)
    a = ap.parse_args()
    c0 = resource.getrusage(resource.RUSAGE_SELF).ru_utime
    t0 = time.perf_counter()
    s = dc.bench(warmstarts=["zero", PyZero(), "builtin", dc.PyBuiltin()], seeds=a.seeds, steps=a.steps,
                 sweeps=a.sweeps)
    wall = time.perf_counter() - t0
    cpu = resource.getrusage(resource.RUSAGE_SELF).ru_utime - c0
    ws = s["warmstarters"]
    print(f"seed scene, seeds {a.seeds}, {a.steps} steps, {s['evaluated_steps']} evaluated steps "
          f"(wall {wall:.1f} s, CPU {cpu:.1f} s)")
    print(f"{'starter':12} {'median warm start [µs]':>24} {'median sweeps':>14}")
    for name in ("zero", "py-zero", "builtin", "py-builtin"):
        print(f"{name:12} {1000 * ws[name]['warmstart_ms']:24.1f} {ws[name]['median_sweeps_to_tol']!s:>14}")
    print(f"Python call overhead (py-zero − zero): {1000 * (ws['py-zero']['warmstart_ms'] - ws['zero']['warmstart_ms']):.1f} µs per call")
    print(f"py-builtin / builtin warm-start time: {ws['py-builtin']['warmstart_ms'] / ws['builtin']['warmstart_ms']:.0f}x")


if __name__ == "__main__":
    main()
