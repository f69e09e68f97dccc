"""The solver comparison from Python: bench(solvers=[...]) (the `--solvers` of `deepcontact bench`)
and solve(p, solver=..., lambda0=...) with the iterative and Newton-type solvers."""
import numpy as np
import pytest

from conftest import SMALL

FIGURES = {"reached_share", "median_ms_to_accuracy", "median_iterations_to_accuracy", "median_total_ms"}


def test_bench_with_solvers_reports_every_pair(dc):
    s = dc.bench(warmstarts=["zero", "builtin"], solvers=["pgs", "nncg"], seeds=(1,), set=SMALL, steps=40, sweeps=200)
    assert set(s["solvers"]) == {"pgs", "nncg"}
    for pairs in s["solvers"].values():
        assert set(pairs) == {"zero", "builtin"}
        for figures in pairs.values():
            assert set(figures) == FIGURES
            assert 0.0 <= figures["reached_share"] <= 1.0
            assert figures["median_total_ms"] > 0
    assert s["accuracy"] == 1e-6
    # The starters' own columns are there as without the comparison.
    assert set(s["warmstarters"]) == {"zero", "builtin"}


def test_bench_without_solvers_has_no_comparison(dc):
    s = dc.bench(warmstarts=["builtin"], seeds=(1,), set=SMALL, steps=30, sweeps=200)
    assert "solvers" not in s and "accuracy" not in s


def test_bench_refuses_a_string_and_an_unknown_solver(dc):
    with pytest.raises(TypeError):
        dc.bench(warmstarts=["builtin"], solvers="pgs", seeds=(1,), set=SMALL, steps=5)
    with pytest.raises(dc.ConfigError):
        dc.bench(warmstarts=["builtin"], solvers=["pgs", "no-such-solver"], seeds=(1,), set=SMALL, steps=5)


def test_solve_from_a_warm_start_with_each_solver(dc):
    """nncg (and newton-sparse where registered) from lambda0 reach pgs's solution of a pile's LCP."""
    w = dc.World(set=SMALL)
    for _ in range(60):
        w.step(sweeps=200)
    w.collide()
    p = w.assemble()
    ref = dc.solve(p, "pgs", sweeps=20000, tol=1e-10)
    assert ref.status == "converged"
    lam0 = np.array(ref.lam)  # the solution itself as the guess
    names = [s for s in ("nncg", "newton-sparse") if s in dc.solvers()]
    assert "nncg" in names
    for name in names:
        r = dc.solve(p, solver=name, lambda0=lam0, sweeps=20000, tol=1e-10)
        assert r.status == "converged", (name, r.message)
        assert r.residual <= 1e-6
        zero = dc.solve(p, solver=name, sweeps=20000, tol=1e-10)
        assert r.sweeps <= zero.sweeps, name  # started at the solution it has less to do
        assert np.allclose(r.lam, ref.lam, atol=1e-6 * max(1.0, np.abs(ref.lam).max()))
    # A guess of the wrong size or with NaN is refused at the door, before any solver runs.
    with pytest.raises(ValueError):
        dc.solve(p, solver="nncg", lambda0=np.zeros(p.rows + 1))
    with pytest.raises(ValueError):
        dc.solve(p, solver="nncg", lambda0=np.full(p.rows, np.nan))
