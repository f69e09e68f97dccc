"""World from Python: bit-equal to `deepcontact simulate`, stage by stage equal to step(),
numpy views that follow the simulation, and the CLI's error messages."""
import numpy as np
import pytest

from conftest import SMALL, cli_error, run_cli, set_args


def simulate_in_python(dc, overrides, warmstart="builtin"):
    w = dc.World(set=overrides)
    for _ in range(overrides["time.steps"]):
        w.step(solver=None, warmstart=warmstart, sweeps=None, tol=None)  # None: the scene's [solver]
    return w


def test_step_is_bit_equal_to_simulate(dc, tmp_path):
    w = simulate_in_python(dc, SMALL)
    cli_hash = run_cli("simulate", *set_args(SMALL), "--hash").stdout.strip()
    assert w.hash == cli_hash
    # The whole final state, not just its hash: the CLI's trajectory holds it.
    run_cli("simulate", *set_args(SMALL), "--out", tmp_path / "run.h5")
    t = dc.read_trajectory(tmp_path / "run.h5")
    assert t.steps == SMALL["time.steps"] and t.bodies == SMALL["bodies.count"]
    assert np.array_equal(t.position[-1], w.bodies.position)
    assert np.array_equal(t.angle[-1], w.bodies.angle)
    assert np.array_equal(t.velocity[-1], w.bodies.velocity)
    assert np.array_equal(t.omega[-1], w.bodies.omega)


def test_morton_numbering_is_the_same_in_python_and_in_trajectories(dc, tmp_path):
    """[bodies] order = "morton" renumbers the generated bodies; Python's views, the CLI's
    trajectory and its hash all show that one numbering, and the bodies are those of the
    creation order."""
    morton = dict(SMALL, **{"bodies.order": "morton"})
    w = simulate_in_python(dc, morton)
    assert w.hash == run_cli("simulate", *set_args(morton), "--hash").stdout.strip()
    run_cli("simulate", *set_args(morton), "--out", tmp_path / "run.h5")
    t = dc.read_trajectory(tmp_path / "run.h5")
    assert np.array_equal(t.position[-1], w.bodies.position)
    start_m = dc.World(set=morton).bodies.position
    start_c = dc.World(set=SMALL).bodies.position
    assert np.array_equal(t.position[0], start_m)
    assert not np.array_equal(start_m, start_c)  # renumbered ...
    by_place = lambda x: x[np.lexsort((x[:, 1], x[:, 0]))]  # rows sorted by (x, y)
    assert np.array_equal(by_place(start_m), by_place(start_c))  # ... the same bodies


def test_default_step_arguments_are_the_seed_solver(dc):
    a, b = dc.World(set={"bodies.count": 10, "bodies.sigma": 2.0}), dc.World(set={"bodies.count": 10, "bodies.sigma": 2.0})
    for _ in range(40):
        a.step()  # "pgs-colored", "builtin", 3000 sweeps, tol 0
        b.step(solver=None, warmstart="builtin", sweeps=None, tol=None)  # the scene's (seed) values
    assert a.hash == b.hash


def builtin_guess(world):
    """λ⁰ of the builtin warm start, written in numpy: previous λ of the contact with the same key."""
    cur, prev = world.contacts, world.previous_contacts
    lam0 = np.zeros(world.rows)
    old = {tuple(k): lam for k, lam in zip(prev.key, prev["lambda"])}
    for c in range(len(cur.key)):
        hit = old.get(tuple(cur.key[c]))
        if hit is not None:
            lam0[cur.normal_row[c]] = hit[0]
            if cur.tangent_row[c] >= 0:
                lam0[cur.tangent_row[c]] = hit[1]
    return lam0


def test_stages_by_hand_equal_step(dc):
    ref = dc.World(set=SMALL)
    w = dc.World(set=SMALL)
    for _ in range(SMALL["time.steps"]):
        ref.step(solver="pgs", sweeps=200)
        w.collide()
        p = w.assemble()
        r = dc.solve(p, "pgs", sweeps=200, tol=0.0, lambda0=builtin_guess(w))
        w.integrate(r.lam)
    assert w.step_index == ref.step_index == SMALL["time.steps"]
    assert w.time == pytest.approx(SMALL["time.steps"] * 0.01)
    assert w.hash == ref.hash


def test_problem_arrays_are_the_assembled_lcp(dc):
    w = dc.World(set=SMALL)
    for _ in range(60):
        w.step(sweeps=200)
    w.collide()
    p = w.assemble()
    n = p.rows
    assert n >= 6
    import scipy.sparse as sp

    assert sp.isspmatrix_csr(p.A) and sp.isspmatrix_csr(p.J)
    assert p.J.shape == (n, 3 * SMALL["bodies.count"]) and p.inv_mass.shape == (3 * SMALL["bodies.count"],)
    A = (p.J @ sp.diags(p.inv_mass) @ p.J.T).toarray() * p.dt
    assert np.allclose(p.A.toarray(), A, rtol=1e-12, atol=1e-12)
    assert p.b.shape == p.lo.shape == p.hi.shape == p.mu.shape == (n,)
    friction = p.normal_row >= 0
    assert np.all(p.mu[friction] == 0.5) and np.all(p.lo[~friction] == 0)
    assert p.b.base is not None  # a view into the problem, not a copy


def test_body_arrays_are_views_that_follow_the_world(dc):
    w = dc.World(set={"bodies.count": 5})
    pos = w.bodies.position
    y0 = pos[:, 1].copy()
    for _ in range(10):
        w.step(sweeps=50)
    assert np.all(pos[:, 1] < y0)  # falling
    assert np.array_equal(pos, w.bodies.position)
    assert np.allclose(w.bodies.mass, np.pi * w.bodies.radius**2)
    assert set(w.bodies) >= {"position", "angle", "velocity", "omega", "mass", "radius"}


def test_scene_as_text_path_and_overrides(dc, tmp_path):
    text = "[bodies]\ncount = 7\n[time]\ndt = 0.005\n"
    f = tmp_path / "s.toml"
    f.write_text(text)
    for w in (dc.World(text), dc.World(str(f)), dc.World(f), dc.World(set={"bodies.count": 7, "time.dt": 0.005})):
        assert len(w.bodies.radius) == 7 and "dt = 0.005" in w.scene
    assert dc.World(set=["bodies.count=3"]).bodies.radius.shape == (3,)
    assert dc.World(set={"world.walls": ["left", "bottom"], "solver.name": "psor"}).scene.count('"left"') == 1


def test_bad_input_raises_the_cli_message(dc, tmp_path):
    with pytest.raises(dc.ConfigError) as e:
        dc.World(set={"bodies.count": -1})
    assert str(e.value) == cli_error("simulate", "--set", "bodies.count=-1", "--steps", "0")
    with pytest.raises(dc.ConfigError) as e:
        dc.World(set={"contact.nosuchkey": 1})
    assert str(e.value) == cli_error("simulate", "--set", "contact.nosuchkey=1", "--steps", "0")
    missing = tmp_path / "missing.toml"
    with pytest.raises(Exception) as e:
        dc.World(str(missing))
    assert str(e.value) == cli_error("simulate", "--scene", missing, "--steps", "0")
    bad = tmp_path / "bad.toml"
    bad.write_text("[world]\nwidth = -3\n")
    with pytest.raises(dc.ConfigError) as e:
        dc.World(bad)
    assert str(e.value) == cli_error("simulate", "--scene", bad, "--steps", "0")
    with pytest.raises(dc.ConfigError) as e:
        dc.World().step(warmstart="nosuch")
    # The CLI's message up to the list of names, which is each registry's own: the module has
    # no research starters (docs/python.md), so its list is warmstarters().
    head, _, names = str(e.value).partition(" (available: ")
    assert head == cli_error("simulate", "--warmstart", "nosuch", "--steps", "1").partition(" (available: ")[0]
    assert names.rstrip(")").split() == sorted(dc.warmstarters())
    w = dc.World(set={"bodies.count": 3})
    w.collide()
    w.assemble()
    with pytest.raises(dc.InvalidArgument):
        w.integrate(np.zeros(w.rows + 1))


def test_step_defaults_are_the_scenes_solver_settings(dc):
    # A scene whose [solver] differs from the seed's: step() without arguments uses it.
    scene = {"bodies.count": 12, "bodies.sigma": 2.0, "solver.sweeps": 7, "solver.tolerance": 1e-3}
    a, b = dc.World(set=scene), dc.World(set=scene)
    for _ in range(30):
        ra = a.step()
        rb = b.step(sweeps=7, tol=1e-3)
        assert ra.sweeps <= 7 and ra.sweeps == rb.sweeps
    assert a.hash == b.hash


def test_copy_and_deepcopy_give_an_independent_world_in_the_same_state(dc):
    import copy

    w = dc.World(set=SMALL)
    for _ in range(20):
        w.step()
    for c in (copy.copy(w), copy.deepcopy(w)):
        assert c.hash == w.hash and c.step_index == w.step_index
        c.step()
        assert c.step_index == w.step_index + 1  # the original did not move
    twin = copy.deepcopy(w)
    for _ in range(10):
        w.step()
        twin.step()
    assert twin.hash == w.hash  # the copy continues bit-equal (previous contacts included)


def test_pickle_round_trip_continues_bit_equal(dc):
    import pickle

    w = dc.World(set=SMALL)
    for _ in range(15):
        w.step()
    w.collide()
    w.assemble()
    w.integrate(None)  # a stage-by-stage step is kept too
    loaded = pickle.loads(pickle.dumps(w))
    assert loaded.hash == w.hash and loaded.step_index == w.step_index
    assert np.array_equal(loaded.previous_contacts["lambda"], w.previous_contacts["lambda"])
    for _ in range(10):
        w.step()
        loaded.step()
    assert loaded.hash == w.hash


def test_render_returns_an_image_of_the_current_state(dc):
    w = dc.World(set={"bodies.count": 10, "bodies.sigma": 2.0})
    for _ in range(5):
        w.step()
    img = w.render()
    assert img.dtype == np.uint8 and img.ndim == 3 and img.shape[2] == 3 and img.shape[0] > 100
    assert len(np.unique(img.reshape(-1, 3), axis=0)) > 10  # something is drawn
