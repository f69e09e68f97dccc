"""Every example in examples/*.py runs (a new example is picked up by the glob), and what the
examples print is right: trajectory energies use each shape's inertia, and the solver
comparison explains every status it prints."""
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import SOURCE, run_cli

EXAMPLES = sorted((SOURCE / "examples").glob("*.py"))


def example_args(name, tmp_path):
    """Command-line arguments (and setup) of each example; the default is none."""
    if name == "read_trajectory.py":
        run_cli("simulate", "--scene", SOURCE / "scenes" / "mixed.toml", "--steps", 120, "--out", tmp_path / "run.h5")
        return [str(tmp_path / "run.h5")]
    if name == "compare_solvers.py":
        return ["--plot", str(tmp_path / "theta.png")]
    return []


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_runs(path, tmp_path):
    p = subprocess.run([sys.executable, str(path), *example_args(path.name, tmp_path)], capture_output=True,
                       text=True, cwd=tmp_path, env=os.environ.copy(), timeout=280)
    assert p.returncode == 0, p.stderr[-2000:]
    assert p.stdout.strip(), f"{path.name} printed nothing"


def test_trajectory_inertia_is_the_engines_for_every_shape(dc, tmp_path):
    # box_pile: boxes; mixed: circles, boxes, polygons and ellipses.
    for scene in ("box_pile.toml", "mixed.toml"):
        out = tmp_path / f"{scene}.h5"
        run_cli("simulate", "--scene", SOURCE / "scenes" / scene, "--steps", 1, "--out", out)
        t = dc.read_trajectory(out)
        w = dc.World(SOURCE / "scenes" / scene)
        n = t.bodies
        engine = np.asarray(w.bodies.inertia)[:n]
        dynamic = np.isfinite(engine) & (engine > 0)
        assert dynamic.any()
        np.testing.assert_allclose(t.inertia[dynamic], engine[dynamic], rtol=1e-9)
        if t.shapes is not None and (t.shapes["kind"] != "circle").any():
            circle_rule = 0.5 * t.mass * t.radius ** 2
            assert not np.allclose(circle_rule[dynamic], engine[dynamic])  # the old example's rule is wrong here


def test_compare_solvers_explains_every_status(tmp_path):
    p = subprocess.run([sys.executable, str(SOURCE / "examples" / "compare_solvers.py")], capture_output=True,
                       text=True, cwd=tmp_path, timeout=280)
    assert p.returncode == 0, p.stderr[-2000:]
    rows = [line.split() for line in p.stdout.splitlines() if line.split() and line.split()[0] in p.stdout
            and len(line.split()) > 1 and line.split()[1] in
            ("converged", "tolerance_reached", "sweep_limit", "diverged", "infeasible", "failed", "invalid_input")]
    assert rows, p.stdout
    for status in {r[1] for r in rows}:
        if status != "converged":
            assert f"{status}:" in p.stdout, f"status {status} is printed but not explained:\n{p.stdout}"
