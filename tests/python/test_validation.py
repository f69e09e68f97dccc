"""Every Python entry point checks sizes, indices and values before C++ touches them, and every
error has a message (docs/robustness.md "Bad values refused at the door")."""
import numpy as np
import pytest
import scipy.sparse


def test_sparse_matrices_with_indices_outside_their_shape_are_value_errors(dc):
    q = np.array([-1.0, -1.0])
    # Column 1000000 of a 2 x 2 matrix once wrote past Eigen's arrays (SIGSEGV).
    with pytest.raises(ValueError, match=r"column index 1000000 .* outside \[0, 2\)"):
        dc.Problem(scipy.sparse.csr_matrix(([1.0, 2.0], [0, 1000000], [0, 1, 2]), shape=(2, 2)), q)
    for bad in (5, -3):
        with pytest.raises(ValueError, match=f"column index {bad}"):
            dc.Problem(scipy.sparse.csr_matrix(([1.0, 2.0], [0, bad], [0, 1, 2]), shape=(2, 2)), q)
    with pytest.raises(ValueError, match="indptr"):
        dc.Problem(scipy.sparse.csr_matrix(([1.0, 2.0], [0, 1], [0, 2, 1]), shape=(2, 2)), q)
    p = dc.Problem(scipy.sparse.csr_matrix(([1.0, 2.0], [0, 1], [0, 1, 2]), shape=(2, 2)), q)  # a valid one
    assert p.rows == 2


def test_vectors_of_the_wrong_length_or_not_finite_are_value_errors(dc):
    p = dc.Problem(np.eye(3), -np.ones(3))
    for call in (lambda: p.residual(np.zeros(2)), lambda: p.velocity(np.zeros(4)),
                 lambda: dc.solve(p, lambda0=np.zeros(5)), lambda: dc.solve(p, lambda0=np.array([0.0, np.nan, 0.0]))):
        with pytest.raises(ValueError) as e:
            call()
        assert str(e.value)
    with pytest.raises(ValueError, match="square"):
        dc.write_lcp_dat("/tmp/never-written.dat", np.ones((2, 3)), np.ones(2))


def test_integrate_refuses_nan_and_inf(dc):
    w = dc.World(set={"bodies.count": 20, "bodies.mean": [15.0, 2.5], "bodies.sigma": 2.0})
    for _ in range(30):
        w.collide()
        p = w.assemble()
        if p.rows:
            break
        w.integrate(np.zeros(0))
    assert p.rows > 0
    before = w.bodies.position.copy()
    for bad in (np.nan, np.inf):
        lam = np.zeros(p.rows)
        lam[0] = bad
        with pytest.raises(dc.InvalidArgument, match="not finite"):
            w.integrate(lam)
    assert np.array_equal(w.bodies.position, before)  # nothing moved


def test_a_binary_file_read_as_lcp_raises_with_a_printable_message(dc, tmp_path):
    f = tmp_path / "binary.dat"
    f.write_bytes(bytes([0x7F, 0x45, 0x4C, 0x46, 0x02, 0x00, 0xFF, 0xFE, 0x0A]) * 8)
    with pytest.raises(OSError) as e:
        dc.read_lcp_dat(str(f))
    message = str(e.value)
    assert message and "binary.dat" in message and "\\x7f" in message and "\n" not in message


def test_scene_values_that_overflow_are_config_errors(dc):
    with pytest.raises(dc.ConfigError, match="overflows"):
        dc.World(set={"bodies.density": 1e308})
