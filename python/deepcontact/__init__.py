"""DeepContact from Python: the engine, the LCP solvers, warm starters (also written in
Python) and the warm-start bench. See docs/python.md.

    import deepcontact as dc
    w = dc.World(set={"bodies.count": 20})
    for _ in range(100):
        report = w.step(warmstart="builtin")
    print(w.bodies.position[:3], report.sweeps)
"""
from __future__ import annotations

import typing

from . import _core
from ._core import (  # noqa: F401  (the C++ core, deepcontact/_core*.so)
    __commit__,
    __version__,
    ConfigError,
    InvalidArgument,
    IoError,
    Problem,
    Result,
    StepView,
    World,
)
from ._signatures import signed as _signed

if typing.TYPE_CHECKING:  # names of the annotations (strings at run time)
    import os
    from typing import Any, Iterable, Mapping, Optional, Sequence, Union

    import numpy
    import numpy.typing

# The C++ functions, wrapped so that inspect.signature (and help()) show their parameters.
copy_hdf5 = _signed(_core.copy_hdf5)
read_lcp_dat = _signed(_core.read_lcp_dat)
read_problem = _signed(_core.read_problem)
solve = _signed(_core.solve)
solvers = _signed(_core.solvers)
warmstarters = _signed(_core.warmstarters)
write_lcp_dat = _signed(_core.write_lcp_dat)
write_problem = _signed(_core.write_problem)
from ._core import bench as _bench


class Fields(dict):
    """A dict of numpy arrays with attribute access: ``w.bodies.position`` is
    ``w.bodies["position"]``; ``getattr(c, "lambda")`` or ``c["lambda"]`` for the keyword."""

    __slots__ = ()

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __dir__(self):
        return list(self.keys())


class WarmStarter:
    """Base class of warm starters written in Python.

    Override ``initial_guess(view)`` (return λ⁰, one float per row of
    ``view.world.problem``: ``len == view.rows``), optionally ``name()`` (default: the class
    name), ``observe(view, solved)`` (called after each step's solve with the solved λ) and
    ``uses_oracle()`` (True when the guess uses ``view.oracle``, this step's λ*; such a
    starter is an upper bound, marked ``*`` in bench reports). ``view.world`` is a read-only
    :class:`World` valid during the call only.
    """

    def name(self) -> str:
        """The name in bench reports (default: the class name)."""
        return type(self).__name__

    def initial_guess(self, view: StepView) -> numpy.typing.ArrayLike:  # pragma: no cover - abstract
        """λ⁰ for this step: one float per row of ``view.world.problem`` (``len == view.rows``)."""
        raise NotImplementedError(f"{type(self).__name__}.initial_guess(view) is not implemented")

    def observe(self, view: StepView, solved: numpy.typing.NDArray[numpy.float64]) -> None:
        """Called after each step's solve with the solved λ (default: nothing)."""

    def uses_oracle(self) -> bool:
        """True when the guess uses ``view.oracle`` (this step's λ*): an upper bound, marked ``*``."""
        return False


_DEFAULT_SEEDS = (1, 2)


def bench(scene: Union[str, os.PathLike[str], None] = None,
          warmstarts: Optional[Sequence[Union[str, WarmStarter, type]]] = None,
          seeds: Union[Iterable[int], int, str] = _DEFAULT_SEEDS, quick: bool = False, mode: str = "paired",
          out: Union[str, os.PathLike[str], None] = None, *,
          set: Union[Mapping[str, object], Sequence[str], str] = {}, sweeps: Optional[int] = None,
          tol: float = 1e-2, solver: str = "pgs-colored", steps: Optional[int] = None, model: str = "",
          progress: bool = False, solvers: Optional[Sequence[str]] = None, accuracy: float = 1e-6,
          jobs: int = 1) -> dict[str, Any]:
    """Run the warm-start benchmark of ``deepcontact bench`` and return its summary as a dict
    (the content of summary.json; with ``out`` the whole report is written there too).

    warmstarts: names of warmstarters() ("zero", "builtin", "cnn", …; None = the CLI's default
    list without its oracles and controls) and/or Python warm starters. An instance is used for every seed; a class (or factory) is called
    once per seed for a fresh starter, as the C++ ones are. seeds: an iterable of ints, an int,
    or "A..B". quick: as ``--quick`` (one seed unless ``seeds`` is given, the short starter
    list). sweeps/tol/solver/steps/model/set: as the CLI's options. The GIL is released
    while C++ runs (Python starters take it for their calls).

    solvers: a list of solver names (e.g. ["pgs", "nncg", "newton-sparse"]) adds the solver
    comparison of ``--solvers`` (paired mode): every solver solves every step from every
    starter's guess, and the summary gains "solvers": {SOLVER: {STARTER: {"reached_share",
    "median_ms_to_accuracy", "median_iterations_to_accuracy", "median_total_ms"}}}.
    accuracy: its target R (``--accuracy``): natural-map residual <= R x the heaviest body's
    weight m g (default 1e-6; docs/bench.md "Solver comparison").

    jobs: seeds run at once, each on its own thread (``--jobs``); every figure but the timings
    equals ``jobs=1``'s (docs/bench.md "Parallel seeds").
    """
    if quick and seeds is _DEFAULT_SEEDS:
        seeds = (1,)
    return _bench(scene=scene, set=set, warmstarts=warmstarts, seeds=seeds, quick=quick, mode=mode, out=out,
                  sweeps=sweeps, tol=tol, solver=solver, steps=steps, model=model, progress=progress,
                  solvers=solvers, accuracy=accuracy, jobs=jobs)


from .trajectory import Trajectory, read_trajectory  # noqa: E402,F401
from .starters import PyBuiltin, previous_lambda_by_key  # noqa: E402,F401


def render(trajectory: Union[str, os.PathLike[str]], out: Union[str, os.PathLike[str]], frame: Optional[int] = None,
           every: Optional[int] = None, progress: bool = True) -> int:
    """Draw a trajectory file (``deepcontact render``): a GIF/MP4 of every ``every``-th
    step, or with ``frame=K`` one PNG of state K with the forces of step K. Returns the
    number of frames written; a wrong extension, an ``out`` that is a directory or a frame
    out of range raise ``render_trajectory.RenderError`` (one line) before anything is drawn."""
    import os

    from . import render_trajectory

    out = str(out)
    render_trajectory.check_output(out, frame, every)  # the path the user gave, not the temporary
    # Drawn into OUT.tmp.EXT (the extension picks the format) and renamed onto OUT only when
    # complete: a failed or interrupted render leaves an earlier OUT as it was.
    tmp = out + ".tmp" + os.path.splitext(out)[1]
    try:
        n = render_trajectory.render(str(trajectory), tmp, frame=frame, every=every, progress=progress)
    except BaseException as e:
        if os.path.isfile(tmp):
            os.remove(tmp)
        if isinstance(e, render_trajectory.RenderError):  # name the file the caller asked for
            raise render_trajectory.RenderError(str(e).replace(tmp, out)) from None
        raise
    from ._core import _commit_file

    _commit_file(tmp, out)
    return n


def _render_world(world):
    """World.render(): the current state written as a one-state trajectory and drawn."""
    import os
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "state.h5")
        world._write_trajectory(path)
        return read_trajectory(path).frame(0)


__all__ = [
    "ConfigError", "InvalidArgument", "IoError", "Problem", "Result", "StepView", "World", "Fields",
    "WarmStarter", "bench", "read_lcp_dat", "write_lcp_dat", "read_problem", "write_problem", "copy_hdf5",
    "solve", "solvers", "warmstarters",
    "Trajectory", "read_trajectory", "render", "PyBuiltin", "previous_lambda_by_key",
]
