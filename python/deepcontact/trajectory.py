"""Reader of the HDF5 trajectories of ``deepcontact simulate --out run.h5`` (layout:
docs/formats.md, "Trajectory") into numpy arrays.

    t = read_trajectory("run.h5")
    t.position[k]          # (n, 2) centres at state k (k = 0 … steps)
    c = t.step_contacts(k) # contacts solved in step k: point, normal, lambda, …

Pure h5py/numpy (no C++ needed), so ``deepcontact render`` can use it from the source tree.
"""
from __future__ import annotations

import tomllib
import typing

import numpy as np

try:
    from ._core import IoError  # inside the deepcontact package
except ImportError:  # loaded on its own (bench/plots/render_trajectory.py)
    class IoError(OSError):
        """A file could not be read or is not what it should be (one line, naming it)."""

if typing.TYPE_CHECKING:  # names of the annotations (strings at run time)
    import os
    from typing import Optional, Union

FORMAT = "deepcontact-trajectory"
WALL_NAMES = {-1: "left", -2: "right", -3: "bottom", -4: "top"}
SHAPE_KINDS = {0: "circle", 1: "polygon", 2: "ellipse", 3: "box"}


def _attr(f, name, default=None):
    v = f.attrs.get(name, default)
    return v.decode() if isinstance(v, bytes) else v


class Trajectory:
    """All datasets of a trajectory file as numpy arrays (S = steps, n = bodies, C = contacts).

    position (S+1, n, 2), angle (S+1, n), velocity (S+1, n, 2), omega (S+1, n), radius (n),
    mass (n), step_offset (S+1), contacts (Fields-like dict: body_a, body_b, point, normal,
    gap, lambda over all steps), solver (sweeps, status, theta_final, residual per step),
    scene (TOML text), scene_dict (parsed), width, height, walls, dt, warmstart, start_step
    (steps before state 0: state k is at time (start_step + k)·dt),
    shapes (None for circle-only files; else kind (n,) of str, and where present
    vertex_offset (n+1), vertices (V, 2) in the body frame, semi_axes (n, 2)).
    """

    def __init__(self, path: Union[str, os.PathLike[str]]) -> None:
        import h5py  # imported here: `import deepcontact` must not need h5py

        self.path = str(path)
        try:
            f = h5py.File(self.path, "r")
        except (OSError, FileNotFoundError) as e:
            raise IoError(f"{self.path}: cannot open the trajectory: {e}") from None
        with f:
            fmt = _attr(f, "format")
            if fmt != FORMAT:
                raise IoError(f"{self.path}: not a deepcontact trajectory (format attribute {fmt!r}, expected '{FORMAT}')")
            self.format_version = int(_attr(f, "format_version", 0))
            self.scene = _attr(f, "scene", "") or ""
            self.warmstart = _attr(f, "warmstart", "") or ""
            # Steps taken before state 0 (the bench's reference starts after its warm-up).
            self.start_step = int(_attr(f, "start_step", 0))

            def read(name, ndim, required=True):
                if name not in f:
                    if required:
                        raise IoError(f"{self.path}: {name}: dataset missing")
                    return None
                a = f[name][()]
                if a.ndim != ndim:
                    raise IoError(f"{self.path}: {name}: dataset has {a.ndim} dimensions but {ndim} were expected")
                return a

            self.position = read("/bodies/position", 3)
            self.angle = read("/bodies/angle", 2)
            self.velocity = read("/bodies/velocity", 3)
            self.omega = read("/bodies/omega", 2)
            self.radius = read("/bodies/radius", 1)
            self.mass = read("/bodies/mass", 1)
            self.step_offset = read("/contacts/step_offset", 1)
            self.contacts = {
                "body_a": read("/contacts/body_a", 1),
                "body_b": read("/contacts/body_b", 1),
                "point": read("/contacts/point", 2),
                "normal": read("/contacts/normal", 2),
                "gap": read("/contacts/gap", 1),
                "lambda": read("/contacts/lambda", 2),
            }
            self.solver = {k: read(f"/solver/{k}", 1, required=False)
                           for k in ("sweeps", "status", "theta_final", "residual")}
            self.shapes = self._read_shapes(f)
        states, n = self.position.shape[0], self.position.shape[1]
        if self.step_offset.shape[0] != states:
            raise IoError(f"{self.path}: /contacts/step_offset has {self.step_offset.shape[0]} entries, "
                          f"/bodies/position {states} states")
        if self.radius.shape[0] != n:
            raise IoError(f"{self.path}: /bodies/radius has {self.radius.shape[0]} entries for {n} bodies")
        try:
            self.scene_dict = tomllib.loads(self.scene) if self.scene else {}
        except tomllib.TOMLDecodeError as e:
            raise IoError(f"{self.path}: the scene attribute is not valid TOML: {e}") from None
        world = self.scene_dict.get("world", {})
        self.width = float(world.get("width", 30.0))
        self.height = float(world.get("height", 30.0))
        self.walls = list(world.get("walls", ["left", "right", "bottom", "top"]))
        self.dt = float(self.scene_dict.get("time", {}).get("dt", 0.01))

    @staticmethod
    def _read_shapes(f):
        """The shape table (docs/formats.md) when the file has one: wherever the writer puts it, under
        /shapes or /bodies. Circle-only files of format 1 have none; format 2 writes one for
        every file (all circles for a circle-only scene)."""
        import h5py  # as in __init__: `import deepcontact` must not need h5py
        for group in ("/bodies/shape", "/shapes", "/bodies"):
            if group not in f or not isinstance(f[group], h5py.Group):
                continue
            g = f[group]
            kind_name = next((k for k in ("kind", "shape") if k in g and isinstance(g[k], h5py.Dataset)), None)
            if kind_name is None:
                continue
            raw = g[kind_name][()]
            kinds = [SHAPE_KINDS.get(int(k), str(k)) if np.issubdtype(np.asarray(k).dtype, np.integer)
                     else (k.decode() if isinstance(k, bytes) else str(k)) for k in raw]
            shapes = {"kind": np.array(kinds)}
            for key in ("vertex_offset", "vertices", "semi_axes", "motion"):
                if key in g:
                    shapes[key] = g[key][()]
            return shapes
        return None

    @property
    def steps(self) -> int:
        """Number of steps S (states are 0 … S)."""
        return self.position.shape[0] - 1

    @property
    def bodies(self) -> int:
        """Number of bodies n (the last state's; bodies that enter later are NaN before)."""
        return self.position.shape[1]

    @property
    def inertia(self) -> np.typing.NDArray[np.float64]:
        """Moment of inertia of each body about its centre (n,) [kg·m²], from its shape and
        mass (uniform density): circle ½·m·r², ellipse ¼·m·(a² + b²), polygon (and box) from
        its body-frame vertices. The engine's values (``World.bodies.inertia``) are the same."""
        inertia = 0.5 * self.mass * self.radius ** 2
        if self.shapes is None:
            return inertia
        kinds = self.shapes["kind"]
        for b in range(self.bodies):
            if kinds[b] == "ellipse" and "semi_axes" in self.shapes:
                a_, b_ = self.shapes["semi_axes"][b]
                inertia[b] = 0.25 * self.mass[b] * (a_ * a_ + b_ * b_)
            elif kinds[b] in ("polygon", "box"):
                v = self.polygon(b)
                if v is not None:
                    inertia[b] = _polygon_inertia(v, self.mass[b])
        return inertia

    def time(self, k: int) -> float:
        """Simulated time of state k [s]: (start_step + k)·dt (a file recorded after a warm-up
        keeps its true time)."""
        return (self.start_step + k) * self.dt

    def frame(self, k: int) -> np.typing.NDArray[np.uint8]:
        """State k drawn as ``deepcontact render --frame k`` draws it (bodies, walls, the forces
        solved in step k, time and step): an (H, W, 3) uint8 numpy array, e.g. for
        ``PIL.Image.fromarray(t.frame(k))`` or ``plt.imshow`` in a notebook."""
        if not 0 <= k <= self.steps:
            raise IndexError(f"{self.path}: state {k} is outside 0..{self.steps}")
        from . import render_trajectory
        import matplotlib.pyplot as plt

        scene = render_trajectory.Scene(self)
        try:
            return scene.draw(k)
        finally:
            plt.close(scene.fig)

    def step_contacts(self, k: int) -> dict[str, np.typing.NDArray]:
        """The contacts solved in step k (found at state k); empty for k = S."""
        if not 0 <= k <= self.steps:
            raise IndexError(f"{self.path}: step {k} is outside 0..{self.steps}")
        lo = int(self.step_offset[k])
        hi = int(self.step_offset[k + 1]) if k < self.steps else lo
        return {name: a[lo:hi] for name, a in self.contacts.items()}

    def polygon(self, body: int) -> Optional[np.typing.NDArray[np.float64]]:
        """Body-frame vertices (m, 2) of a polygon body, or None."""
        if self.shapes is None or "vertices" not in self.shapes or "vertex_offset" not in self.shapes:
            return None
        off = self.shapes["vertex_offset"]
        if off[body + 1] <= off[body]:
            return None
        return self.shapes["vertices"][off[body]:off[body + 1]]

    def __len__(self) -> int:
        return self.position.shape[0]

    def __repr__(self):
        return f"<deepcontact.Trajectory {self.path}: {self.bodies} bodies, {self.steps} steps>"


def _polygon_inertia(v, mass):
    """Inertia of a uniform convex polygon (vertices (m, 2), CCW) about its centroid [kg·m²]:
    I_O = m / (6 Σ c_i) · Σ c_i (p_i·p_i + p_i·p_j + p_j·p_j), c_i = p_i × p_j, j = i + 1;
    then I = I_O − m |centroid|² (parallel axes)."""
    p, q = v, np.roll(v, -1, axis=0)
    c = p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]
    about_origin = mass / (6 * c.sum()) * (c * ((p * p).sum(1) + (p * q).sum(1) + (q * q).sum(1))).sum()
    centroid = ((p + q) * c[:, None]).sum(0) / (3 * c.sum())
    return about_origin - mass * (centroid @ centroid)


def read_trajectory(path: Union[str, os.PathLike[str]]) -> Trajectory:
    """A trajectory file as a :class:`Trajectory` (IoError with one line naming the file)."""
    return Trajectory(path)
