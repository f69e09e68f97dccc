#!/usr/bin/env python3
"""A warm starter written in Python, benchmarked against the C++ ones.

    PYTHONPATH=build/python /usr/bin/python3 examples/custom_warm_starter.py

`builtin-weight`: the previous step's λ of the contact with the same key (as builtin), and
for a contact that is new this step the weight of the lighter body, m·|g|, instead of 0.
"""
import numpy as np

import deepcontact as dc


class BuiltinWeight(dc.WarmStarter):
    def name(self):
        return "builtin-weight"

    def initial_guess(self, view):
        lam0, new = dc.previous_lambda_by_key(view)  # builtin's rule
        w = view.world
        cur, mass = w.contacts, w.bodies.mass
        for c in np.flatnonzero(new):  # new contact: the weight of the lighter of its bodies
            a, b = cur.body_a[c], cur.body_b[c]
            lam0[cur.normal_row[c]] = 9.81 * (mass[b] if a < 0 else min(mass[a], mass[b]))
        return lam0

if __name__ == "__main__":
    s = dc.bench(warmstarts=["zero", "builtin", BuiltinWeight()], seeds=(1,), steps=300, sweeps=1000)
    print(f"{'starter':16} {'median sweeps':>14} {'warm start ms':>14}")
    for name, row in s["warmstarters"].items():
        print(f"{name:16} {row['median_sweeps_to_tol'] or 'never':>14} {row['warmstart_ms']:14.4f}")
