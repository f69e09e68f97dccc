#!/usr/bin/env python3
"""Read a trajectory (deepcontact simulate --out run.h5) into numpy and summarise it.

    build/bin/deepcontact simulate --out run.h5      # any scene: --scene scenes/mixed.toml
    PYTHONPATH=build/python /usr/bin/python3 examples/read_trajectory.py run.h5
"""
import sys

import numpy as np

import deepcontact as dc

t = dc.read_trajectory(sys.argv[1] if len(sys.argv) > 1 else "run.h5")
print(t)  # bodies, steps
# Per-body inertia from each body's shape (circles, boxes, polygons, ellipses), not ½ m r²;
# static bodies (infinite mass, zero velocity) and bodies not yet entered (NaN) add nothing.
dynamic = np.isfinite(t.mass) & (t.mass > 0)
inertia = t.inertia
with np.errstate(invalid="ignore"):
    kinetic = 0.5 * np.nansum(t.mass[dynamic] * (t.velocity[:, dynamic] ** 2).sum(axis=2)
                              + inertia[dynamic] * t.omega[:, dynamic] ** 2, axis=1)  # (S+1,)
height = np.nanmean(t.position[:, dynamic, 1], axis=1)
per_step = np.diff(t.step_offset)  # contacts solved in each step
lam_n = t.contacts["lambda"][:, 0]
weight = (t.mass[dynamic] * 9.81).sum()
for k in range(0, t.steps, max(1, t.steps // 10)):
    c = t.step_contacts(k)
    print(f"t = {t.time(k):5.2f} s  mean height {height[k]:6.2f} m  kinetic {kinetic[k]:9.2f} J  "
          f"{per_step[k]:4d} contacts  Σ λ_n on the floor {c['lambda'][c['body_a'] == -3, 0].sum():8.1f} N")
print(f"total weight {weight:.1f} N; largest contact force {lam_n.max() if lam_n.size else 0.0:.1f} N")
