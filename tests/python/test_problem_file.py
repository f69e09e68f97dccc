"""read_problem / write_problem: Siconos 2D frictional-contact .dat and FCLIB .hdf5 from
Python, round trips, engine problems exported, and (when python3-siconos is installed) the
same problem solved by Siconos' 2D Lemke."""
import numpy as np
import pytest

from conftest import SMALL, SOURCE

DATA = SOURCE / "tests" / "data" / "fc2d"


def test_read_problem_gives_the_frictional_problem_and_its_lcp(dc):
    f = dc.read_problem(str(DATA / "FrictionContactProblem00071.dat"))
    assert f.kind == "fc2d" and f.format == "siconos-fc"
    assert f.W.shape == (178, 178) and len(f.q) == 178 and len(f.mu) == 89
    assert np.all(f.problem.normal_row[1::2] == np.arange(0, 178, 2))
    assert np.array_equal(f.problem.mu[1::2], f.mu)
    r = dc.solve(f.problem, solver="newton")
    assert r.status == "converged"
    assert f.solution is None and f.guesses == []
    lcp = dc.read_problem(str(SOURCE / "tests" / "data" / "lcp" / "small_spd.dat"))
    assert lcp.kind == "lcp" and lcp.mu is None


def test_write_problem_round_trips_bit_equal_with_solution_and_guesses(dc, tmp_path):
    f = dc.read_problem(str(DATA / "FrictionContactProblem00031.dat"))
    r = dc.solve(f.problem, solver="newton").lam
    g = np.zeros_like(r)
    h5 = tmp_path / "p.hdf5"
    dc.write_problem(h5, f, solution=r, guesses=[g, r])
    back = dc.read_problem(h5)
    assert back.kind == "fc2d" and back.format == "fclib"
    assert (back.W != f.W).nnz == 0
    assert np.array_equal(back.q, f.q) and np.array_equal(back.mu, f.mu)
    assert np.array_equal(back.solution, r)
    assert len(back.guesses) == 2 and np.array_equal(back.guesses[1], r)
    dat = tmp_path / "p.dat"
    dc.write_problem(dat, {"W": f.W, "q": f.q, "mu": f.mu})
    again = dc.read_problem(dat)
    assert (again.W != f.W).nnz == 0 and np.array_equal(again.q, f.q)


def test_an_engine_problem_is_exported_per_contact(dc, tmp_path):
    w = dc.World(set=SMALL)
    for _ in range(60):
        rep = w.step(solver="newton")
    p = w.problem
    lam = rep.lam if hasattr(rep, "lam") else dc.solve(p, solver="newton").lam
    path = tmp_path / "step.hdf5"
    dc.write_problem(path, p, solution=lam)
    back = dc.read_problem(path)
    n = len(back.q)
    assert n >= len(p)  # frictionless contacts gain a decoupled tangent row
    assert back.problem.residual(back.solution) == pytest.approx(p.residual(lam), abs=1e-12)


def test_malformed_files_raise_one_line_ioerror(dc, tmp_path):
    bad = tmp_path / "bad.dat"
    bad.write_text("3\n1\n0\n3\n3\n")
    with pytest.raises(dc.IoError) as e:
        dc.read_problem(bad)
    assert "dimension 3" in str(e.value) and "\n" not in str(e.value)


def test_siconos_lemke_finds_our_solution(dc, tmp_path):
    sn = pytest.importorskip("siconos.numerics")
    f = dc.read_problem(str(DATA / "FrictionContactProblem00071.dat"))
    ours = dc.solve(f.problem, solver="newton").lam
    path = tmp_path / "ours.dat"
    dc.write_problem(path, f)
    fc = sn.frictionContact_new_from_filename(str(path))
    r, u = np.zeros(len(f.q)), np.zeros(len(f.q))
    opt = sn.SolverOptions(sn.SICONOS_FRICTION_2D_LEMKE)
    assert sn.fc2d_driver(fc, r, u, opt) == 0
    assert np.max(np.abs(r - ours)) <= 1e-7 * max(1.0, np.max(np.abs(ours)))
