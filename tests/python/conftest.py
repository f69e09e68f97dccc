"""Shared fixtures of the Python module's tests (run by ctest: python.test_*; or by hand:
PYTHONPATH=build/python DC_CLI=build/bin/deepcontact /usr/bin/python3 -m pytest tests/python)."""
import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("DC_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
CLI = os.environ.get("DC_CLI", str(SOURCE / "build" / "bench" / "deepcontact"))

# A small scene that still piles up (contacts with friction, a few hundred rows).
SMALL = {"bodies.count": 25, "bodies.sigma": 3.0, "bodies.mean": [15.0, 7.0], "time.steps": 80, "solver.sweeps": 200}


def set_args(overrides):
    """The --set arguments of a dict of overrides (as World(set=…) writes them)."""
    out = []
    for k, v in overrides.items():
        out += ["--set", f"{k}={v}"]
    return out


def run_cli(*args, check=True):
    p = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError(f"deepcontact {' '.join(map(str, args))} failed ({p.returncode}): {p.stderr}")
    return p


def cli_error(*args):
    """The one-line message of a failing CLI call, without the 'deepcontact: error: ' prefix."""
    p = run_cli(*args, check=False)
    assert p.returncode != 0, f"deepcontact {' '.join(map(str, args))} unexpectedly succeeded"
    line = p.stderr.strip().splitlines()[-1]
    prefix = "deepcontact: error: "
    assert line.startswith(prefix), line
    return line[len(prefix):]


@pytest.fixture(scope="session")
def dc():
    import deepcontact

    return deepcontact
