"""solve() from Python against `deepcontact lcp solve` on the same .dat files."""
import json
import pathlib

import numpy as np
import pytest

from conftest import SOURCE, cli_error, run_cli


def random_lcp(n, seed):
    rng = np.random.default_rng(seed)
    B = rng.normal(size=(n, n))
    return B @ B.T + n * np.eye(n), rng.normal(size=n)


@pytest.mark.parametrize("solver,sweeps,tol", [("lemke", 3000, 1e-10), ("pgs-assembled", 300, 0.0),
                                               ("psor", 500, 1e-12), ("newton", 3000, 1e-10)])
def test_solve_equals_cli_lcp_solve(dc, tmp_path, solver, sweeps, tol):
    M, q = random_lcp(12, 7)
    f = tmp_path / "p.dat"
    dc.write_lcp_dat(f, M, q)
    cli = json.loads(run_cli("lcp", "solve", f, "--solver", solver, "--sweeps", sweeps, "--tol", tol,
                             check=False).stdout)
    r = dc.solve(dc.read_lcp_dat(str(f)), solver=solver, sweeps=sweeps, tol=tol)
    assert r.status == cli["status"] and r.sweeps == cli["sweeps"]
    assert np.array_equal(r.lam, np.array(cli["z"]))  # %.17g JSON: exact
    assert r.residual == cli["residual"]


def test_shipped_dat_files_solve_alike(dc):
    files = sorted((SOURCE / "tests" / "data" / "lcp").glob("*.dat"))[:6]
    assert files
    for f in files:
        cli = json.loads(run_cli("lcp", "solve", f, check=False).stdout)
        r = dc.solve(dc.read_lcp_dat(str(f)), solver="lemke", sweeps=3000, tol=1e-10)
        assert r.status == cli["status"], f
        assert np.array_equal(r.lam, np.array(cli["z"], dtype=float)), f


def test_round_trip_and_problem_from_python(dc, tmp_path):
    M, q = random_lcp(6, 3)
    f = tmp_path / "r.dat"
    dc.write_lcp_dat(str(f), M, q)
    p = dc.read_lcp_dat(str(f))
    assert np.array_equal(p.A.toarray(), M) and np.array_equal(p.b, q)
    p2 = dc.Problem(M, q)
    exact = dc.solve(p2, "lemke")
    assert exact.status == "converged"
    w = M @ exact.lam + q
    assert np.all(exact.lam >= 0) and np.all(w >= -1e-9) and abs(exact.lam @ w) < 1e-8
    pgs = dc.solve(p2, "pgs-assembled", sweeps=2000, tol=0.0)
    assert len(pgs.theta) == pgs.sweeps == 2000 and pgs.theta[-1] <= pgs.theta[0]
    assert np.allclose(pgs.lam, exact.lam, atol=1e-8)
    assert set(dc.solvers()) >= {"pgs", "pgs-assembled", "psor", "jacobi", "lemke", "newton"}


def test_bad_input_raises_the_cli_message(dc, tmp_path):
    missing = tmp_path / "missing.dat"
    # `lcp solve` reads any problem file (LCP or frictional); read_problem is its Python twin.
    with pytest.raises(dc.IoError) as e:
        dc.read_problem(str(missing))
    assert str(e.value) == cli_error("lcp", "solve", missing)
    with pytest.raises(dc.IoError) as e:
        dc.read_lcp_dat(str(tmp_path))
    assert "is a directory" in str(e.value)
    bad = tmp_path / "bad.dat"
    bad.write_text("3\n0\n3\n3\n3\t3\n1 2 x\n")
    with pytest.raises(dc.IoError) as e:
        dc.read_lcp_dat(str(bad))
    assert str(e.value) == cli_error("lcp", "solve", bad)
    M, q = random_lcp(3, 1)
    good = tmp_path / "good.dat"
    dc.write_lcp_dat(str(good), M, q)
    with pytest.raises(dc.ConfigError) as e:
        dc.solve(dc.read_lcp_dat(str(good)), solver="nosuch")
    assert str(e.value) == cli_error("lcp", "solve", good, "--solver", "nosuch")
    with pytest.raises(dc.InvalidArgument):
        dc.Problem(M, q[:2])
