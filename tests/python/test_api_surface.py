"""What a user sees of the package: every public name is in the stubs and the docs, every
function has an inspectable signature, and a wrong argument is named in the error."""
import __future__
import inspect
import re

import numpy as np
import pytest

from conftest import SOURCE


def public_names(dc):
    """dir(deepcontact) without private names, submodules and the `annotations` future flag."""
    return {n for n in dir(dc) if not n.startswith("_") and not inspect.ismodule(getattr(dc, n))
            and not isinstance(getattr(dc, n), __future__._Feature)}


def test_public_names_are_in_the_stubs_and_the_stubs_in_the_docs(dc):
    stub = (SOURCE / "python" / "deepcontact" / "__init__.pyi").read_text()
    stubbed = set(re.findall(r"^(?:class|def) ([A-Za-z]\w*)", stub, re.M))
    assert public_names(dc) <= stubbed, f"no stub for {sorted(public_names(dc) - stubbed)}"
    doc = (SOURCE / "docs" / "python.md").read_text()
    undocumented = sorted(n for n in stubbed if f"`{n}`" not in doc)
    assert not undocumented, f"docs/python.md does not list {undocumented}"
    assert set(dc.__all__) == public_names(dc)


def test_every_public_function_has_a_signature(dc):
    params = list(inspect.signature(dc.solve).parameters)
    assert params == ["problem", "solver", "sweeps", "tol", "lambda0", "omega", "record_theta"]
    assert inspect.signature(dc.solve).parameters["solver"].default == "pgs"
    for name in public_names(dc):
        obj = getattr(dc, name)
        if callable(obj) and not inspect.isclass(obj):
            inspect.signature(obj)  # raises for a builtin without one


def test_no_public_member_of_the_stubs_is_typed_any_where_the_type_is_known():
    stub = (SOURCE / "python" / "deepcontact" / "__init__.pyi").read_text()
    for member in ("def step", "def bodies", "def contacts", "def read_problem", "def bench", "def collide"):
        line = next(ln for ln in stub.splitlines() if ln.strip().startswith(member + "("))
        assert "-> Any" not in line and ": Any" not in line, line


def test_a_problem_whose_a_is_not_square_says_so(dc):
    with pytest.raises(dc.InvalidArgument, match=r"A must be square.*3 x 2"):
        dc.Problem(np.ones((3, 2)), np.ones(3))


@pytest.mark.parametrize("value", [5, 2.5, None.__class__])
def test_world_set_of_a_wrong_type_names_set_and_the_expected_types(dc, value):
    with pytest.raises(TypeError, match=r"^set: expected a dict .* or a list of .*strings, got (int|float|type)$"):
        dc.World(set=value)


def test_world_set_takes_one_override_as_a_string(dc):
    assert len(dc.World(set="bodies.count=7").bodies.mass) == 7


def test_write_problem_takes_a_result_as_solution_and_guess(dc, tmp_path):
    w = dc.World(set={"bodies.count": 12})
    for _ in range(30):
        w.step()
    p = w.problem
    r = dc.solve(p, solver="newton", sweeps=100)
    dc.write_problem(tmp_path / "a.hdf5", p, solution=r, guesses=[r])
    dc.write_problem(tmp_path / "b.hdf5", p, solution=r.lam, guesses=[r.lam])
    a, b = dc.read_problem(tmp_path / "a.hdf5"), dc.read_problem(tmp_path / "b.hdf5")
    assert np.array_equal(a.solution, b.solution) and np.array_equal(a.guesses[0], b.guesses[0])
