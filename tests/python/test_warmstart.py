"""Warm starters written in Python: a re-implementation of builtin gives exactly the C++
builtin's sweeps in a paired bench; oracle starters; errors raised inside Python."""
import h5py
import numpy as np
import pytest

from conftest import SMALL

BENCH = dict(seeds=(1,), steps=70, sweeps=300, set={"bodies.count": 25, "bodies.sigma": 3.0, "bodies.mean": [15.0, 7.0]})


def per_step_sweeps(results_h5):
    with h5py.File(results_h5, "r") as f:
        names = [n.decode() if isinstance(n, bytes) else n for n in f["/warmstarter_names"][()]]
        groups = [g.decode() if isinstance(g, bytes) else g for g in f["/warmstarter_groups"][()]]
        return {n: f[f"/warmstarters/{g}/sweeps_to_tol"][()] for n, g in zip(names, groups)}


def test_python_builtin_gives_exactly_the_builtin_sweeps(dc, tmp_path):
    summary = dc.bench(warmstarts=["zero", "builtin", dc.PyBuiltin()], out=tmp_path / "b", **BENCH)
    s = per_step_sweeps(tmp_path / "b" / "results.h5")
    assert len(s["builtin"]) > 30
    assert np.array_equal(s["py-builtin"], s["builtin"])
    assert not np.array_equal(s["zero"], s["builtin"])  # the comparison can tell starters apart
    ws = summary["warmstarters"]
    assert list(ws) == ["zero", "builtin", "py-builtin"]  # in the report like the built-in ones
    assert ws["py-builtin"]["median_sweeps_to_tol"] == ws["builtin"]["median_sweeps_to_tol"]
    report = (tmp_path / "b" / "report.md").read_text()
    assert "py-builtin" in report and "reference_frame.png" in report
    assert (tmp_path / "b" / "reference_frame.png").stat().st_size > 10000


def test_summary_without_out_has_the_summary_json_content(dc):
    s = dc.bench(warmstarts=["builtin"], **BENCH)
    assert set(s) >= {"warmstarters", "statistics", "scene", "seeds", "mode", "solver", "sweeps", "tolerance",
                      "evaluated_steps", "git", "machine"}
    assert s["seeds"] == [1] and s["mode"] == "paired" and s["sweeps"] == 300


def test_subclass_with_oracle_and_observe(dc):
    class Copy(dc.WarmStarter):
        observed = 0

        def uses_oracle(self):
            return True

        def initial_guess(self, view):
            assert view.oracle is not None and len(view.oracle) == view.rows
            return view.oracle

        def observe(self, view, solved):
            Copy.observed += 1
            assert solved.shape == (view.rows,)

    s = dc.bench(warmstarts=["builtin", Copy], **BENCH)  # a class: one instance per seed
    assert s["warmstarters"]["Copy"]["uses_oracle"] is True
    assert s["warmstarters"]["Copy"]["median_sweeps_to_tol"] <= 2
    assert Copy.observed == s["evaluated_steps"]


def test_python_starter_drives_world_step(dc):
    a, b = dc.World(set=SMALL), dc.World(set=SMALL)
    starter = dc.PyBuiltin()
    for _ in range(SMALL["time.steps"]):
        ra = a.step(sweeps=200, warmstart="builtin")
        rb = b.step(sweeps=200, warmstart=starter)
        assert ra.sweeps == rb.sweeps
    assert a.hash == b.hash


def test_errors_inside_python_starters_propagate(dc):
    class Broken(dc.WarmStarter):
        def initial_guess(self, view):
            raise ZeroDivisionError("broken starter")

    with pytest.raises(ZeroDivisionError, match="broken starter"):
        dc.bench(warmstarts=[Broken()], **BENCH)

    class Short(dc.WarmStarter):
        def initial_guess(self, view):
            return np.zeros(view.rows - 1)

    with pytest.raises(dc.InvalidArgument, match=r"warm starter 'Short' returned \d+ values for a problem with \d+ rows"):
        dc.bench(warmstarts=[Short()], **BENCH)

    kept = []

    class Keeper(dc.WarmStarter):
        def initial_guess(self, view):
            kept.append(view.world)
            return np.zeros(view.rows)

    w = dc.World(set={"bodies.count": 3})
    w.step(sweeps=10, warmstart=Keeper())
    with pytest.raises(dc.InvalidArgument, match="expired"):
        kept[0].bodies  # the view's world is gone after the call
    with pytest.raises(dc.ConfigError, match="listed twice"):
        dc.bench(warmstarts=["builtin", "builtin"], **BENCH)
