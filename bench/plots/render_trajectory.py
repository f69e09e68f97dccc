#!/usr/bin/env python3
"""deepcontact render: draw a trajectory file (deepcontact simulate --out run.h5).

    render_trajectory.py run.h5 --out run.gif|run.mp4 [--every N]
    render_trajectory.py run.h5 --frame K --out frame.png

Draws the walls, the bodies (circles with a radius line that shows the rotation; polygons
and ellipses from the trajectory's shape table when it has one: SHAPE_LAYERS below is the
extension point), the contact forces of each step (a segment along the normal through the
contact point, length and colour scaled by λ_n) and the time. Frame K shows state K and the
forces solved in step K (from state K). GIF via matplotlib + Pillow; MP4 through ffmpeg.
Run by `deepcontact render` (apps/deepcontact/commands/render_command.cpp) with the Python of $DC_BENCH_PYTHON,
and importable as deepcontact.render_trajectory. Errors: one line on stderr, exit 1.
"""
import argparse
import importlib.util
import math
import os
import shutil
import subprocess
import sys
import time

import numpy as np

try:
    from . import trajectory as _trajectory  # inside the deepcontact package
except ImportError:  # run as a script from bench/plots: the reader lives in python/deepcontact
    _here = os.path.dirname(os.path.abspath(__file__))
    _spec = importlib.util.spec_from_file_location(
        "dc_trajectory", os.path.join(_here, "..", "..", "python", "deepcontact", "trajectory.py"))
    _trajectory = importlib.util.module_from_spec(_spec)
    _spec.loader.exec_module(_trajectory)

IoError = _trajectory.IoError


class RenderError(Exception):
    """A usage or input problem; main() prints it as one line."""


FIGSIZE = (5.6, 5.0)  # inches (560 × 500 px at the default dpi; even, as yuv420p MP4 wants)
DPI = 100
MAX_FPS = 50.0       # GIF frame delays below 20 ms are not honoured by viewers
TARGET_FPS = 25.0    # the default --every aims at real time at this frame rate
FORCE_LENGTH = 1.8   # [m]: the segment length of the force scale's top (≈ one body diameter)
MIN_FORCE_LENGTH = 0.3  # [m]: shortest segment, so that every contact with λ_n > 0 shows
MAX_FORCE_LENGTH = 1.5 * FORCE_LENGTH  # [m]: impact spikes do not cross the pile
BODY_FACE = "#9ecae1"
BODY_EDGE = "#08306b"
WALL_COLOR = "#444444"


# ---- bodies: one layer per shape kind -----------------------------------------------------
class CircleLayer:
    """Circles (EllipseCollection in data units) and a radius line showing the angle."""

    def __init__(self, ax, traj, index):
        from matplotlib.collections import EllipseCollection, LineCollection

        self.index = index
        r = traj.radius[index]
        self.r = r
        self.discs = EllipseCollection(2 * r, 2 * r, np.zeros_like(r), units="xy", offsets=np.zeros((len(r), 2)),
                                       offset_transform=ax.transData, facecolors=BODY_FACE, edgecolors=BODY_EDGE,
                                       linewidths=0.6, zorder=2)
        ax.add_collection(self.discs)
        self.spokes = LineCollection([], colors=BODY_EDGE, linewidths=0.8, zorder=3)
        ax.add_collection(self.spokes)

    def update(self, position, angle):
        x, th = position[self.index], angle[self.index]
        self.discs.set_offsets(x)
        tip = x + self.r[:, None] * np.stack([np.cos(th), np.sin(th)], axis=1)
        self.spokes.set_segments(np.stack([x, tip], axis=1))


class PolygonLayer:
    """Convex polygons (and boxes) from their body-frame vertices, rotated by the angle."""

    def __init__(self, ax, traj, index):
        from matplotlib.collections import PolyCollection

        self.index = index
        self.vertices = [traj.polygon(int(b)) for b in index]
        self.polys = PolyCollection([], facecolors=BODY_FACE, edgecolors=BODY_EDGE, linewidths=0.6, zorder=2)
        ax.add_collection(self.polys)

    def update(self, position, angle):
        out = []
        for b, v in zip(self.index, self.vertices):
            c, s = math.cos(angle[b]), math.sin(angle[b])
            rot = np.array([[c, -s], [s, c]])
            out.append(v @ rot.T + position[b])
        self.polys.set_verts(out)


class EllipseLayer:
    """Ellipses with semi-axes (a, b) rotated by the angle, and a line along the a axis."""

    def __init__(self, ax, traj, index):
        from matplotlib.collections import EllipseCollection, LineCollection

        self.index = index
        ab = traj.shapes["semi_axes"][index]
        self.a = ab[:, 0]
        self.ell = EllipseCollection(2 * ab[:, 0], 2 * ab[:, 1], np.zeros(len(index)), units="xy",
                                     offsets=np.zeros((len(index), 2)), offset_transform=ax.transData,
                                     facecolors=BODY_FACE, edgecolors=BODY_EDGE, linewidths=0.6, zorder=2)
        ax.add_collection(self.ell)
        self.spokes = LineCollection([], colors=BODY_EDGE, linewidths=0.8, zorder=3)
        ax.add_collection(self.spokes)

    def update(self, position, angle):
        x, th = position[self.index], angle[self.index]
        self.ell.set_offsets(x)
        self.ell._angles = np.asarray(th)  # EllipseCollection has no public setter for angles (radians)
        tip = x + self.a[:, None] * np.stack([np.cos(th), np.sin(th)], axis=1)
        self.spokes.set_segments(np.stack([x, tip], axis=1))


# kind (Trajectory.shapes["kind"]) → layer. A new shape kind adds its class here.
SHAPE_LAYERS = {"circle": CircleLayer, "polygon": PolygonLayer, "box": PolygonLayer, "ellipse": EllipseLayer}


def body_layers(ax, traj):
    if traj.shapes is None:
        return [CircleLayer(ax, traj, np.arange(traj.bodies))]
    kinds = traj.shapes["kind"]
    layers = []
    for kind in sorted(set(kinds)):
        index = np.flatnonzero(kinds == kind)
        cls = SHAPE_LAYERS.get(kind)
        if cls is PolygonLayer and any(traj.polygon(int(b)) is None for b in index):
            cls = None
        if cls is EllipseLayer and "semi_axes" not in traj.shapes:
            cls = None
        # Unknown kinds, or a table without the data a kind needs: its bounding circle.
        layers.append((cls or CircleLayer)(ax, traj, index))
    return layers


# ---- the scene ----------------------------------------------------------------------------
class Scene:
    """The figure of one trajectory; draw(k) updates it to state k and returns RGB pixels."""

    def __init__(self, traj, dpi=DPI):
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.collections import LineCollection

        self.traj = traj
        self.fig = plt.figure(figsize=FIGSIZE, dpi=dpi)
        # Fixed boxes (the equal-aspect scene shrinks inside its box): nothing is clipped. The
        # label (time, step, contacts) has its own strip above the scene, off the walls and bodies.
        self.ax = ax = self.fig.add_axes([0.11, 0.09, 0.72, 0.80])
        cax = self.fig.add_axes([0.855, 0.13, 0.028, 0.72])
        w, h = traj.width, traj.height
        pad = 0.03 * max(w, h)
        ax.set_xlim(-pad, w + pad)
        ax.set_ylim(-pad, h + pad)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.tick_params(labelsize=8)
        walls = {"left": [(0, 0), (0, h)], "right": [(w, 0), (w, h)], "bottom": [(0, 0), (w, 0)],
                 "top": [(0, h), (w, h)]}
        for name in traj.walls:
            if name in walls:
                (x0, y0), (x1, y1) = walls[name]
                ax.plot([x0, x1], [y0, y1], color=WALL_COLOR, linewidth=2.5, solid_capstyle="butt", zorder=1)
        self.layers = body_layers(ax, traj)
        lam_n = traj.contacts["lambda"][:, 0] if len(traj.contacts["lambda"]) else np.zeros(1)
        positive = lam_n[lam_n > 0]
        # One scale for the whole run (frames compare): the 99th percentile of λ_n spans
        # FORCE_LENGTH (larger forces get the top colour); length ∝ λ_n, clipped to
        # [MIN_FORCE_LENGTH, MAX_FORCE_LENGTH].
        self.lam_top = float(np.percentile(positive, 99)) if positive.size else 1.0
        from matplotlib.colors import LinearSegmentedColormap

        # Orange → dark red: visible on the light bodies and distinct from their outlines.
        base = plt.get_cmap("YlOrRd")
        self.cmap = LinearSegmentedColormap.from_list("forces", base(np.linspace(0.4, 1.0, 64)))
        self.forces = LineCollection([], linewidths=2.0, zorder=4, capstyle="round")
        ax.add_collection(self.forces)
        sm = plt.cm.ScalarMappable(cmap=self.cmap, norm=plt.Normalize(0, self.lam_top))
        cb = self.fig.colorbar(sm, cax=cax)
        cb.set_label("contact force λ_n [N]", fontsize=8)
        cb.ax.tick_params(labelsize=7)
        self.label = self.fig.text(0.11, 0.985, "", va="top", ha="left", fontsize=9, family="monospace", zorder=5)

    def draw(self, k):
        t = self.traj
        for layer in self.layers:
            layer.update(t.position[k], t.angle[k])
        c = t.step_contacts(k)
        lam = c["lambda"][:, 0]
        on = lam > 0
        p, n, lam = c["point"][on], c["normal"][on], lam[on]
        length = np.clip(FORCE_LENGTH * lam / self.lam_top, MIN_FORCE_LENGTH, MAX_FORCE_LENGTH)
        half = 0.5 * length[:, None] * n
        self.forces.set_segments(np.stack([p - half, p + half], axis=1))
        self.forces.set_color(self.cmap(np.clip(lam / self.lam_top, 0, 1)))
        first = getattr(t, "start_step", 0)  # the bench's reference starts after its warm-up
        self.label.set_text(f"t = {t.time(k):6.2f} s   step {first + k}/{first + t.steps}\n"
                            f"{int(on.sum()):4d} contacts with λ_n > 0")
        self.fig.canvas.draw()
        return np.asarray(self.fig.canvas.buffer_rgba())[:, :, :3].copy()


class Progress:
    """A one-line bar on stderr (only on a terminal), like the C++ commands' ProgressBar."""

    def __init__(self, total, enabled):
        self.total, self.done, self.t0, self.last = max(total, 1), 0, time.monotonic(), 0.0
        self.enabled = enabled and sys.stderr.isatty()

    def advance(self):
        self.done += 1
        now = time.monotonic()
        if not self.enabled or (self.done < self.total and now - self.last < 0.1):
            return
        self.last = now
        frac = self.done / self.total
        el = now - self.t0
        eta = el * (1 - frac) / frac if frac > 0 else 0
        bar = ("#" * int(frac * 30)).ljust(30, ".")
        sys.stderr.write(f"\rrender [{bar}] {self.done}/{self.total} {100 * frac:3.0f}% {el:5.0f}s ETA {eta:5.0f}s\033[K")
        sys.stderr.flush()

    def finish(self):
        if self.enabled:
            sys.stderr.write("\n")


def frame_list(traj, every):
    if every is None:
        every = max(1, round(1.0 / (traj.dt * TARGET_FPS)))
    if every < 1:
        raise RenderError(f"--every must be >= 1, got {every}")
    frames = list(range(0, traj.steps + 1, every))
    if frames[-1] != traj.steps:
        frames.append(traj.steps)
    fps = min(MAX_FPS, 1.0 / (traj.dt * every))
    return frames, fps


def write_gif(scene, frames, fps, out, progress):
    from PIL import Image

    # One palette for all frames (from the first), no dithering: small files, no flicker.
    images = []
    palette = None
    for k in frames:
        rgb = Image.fromarray(scene.draw(k))
        if palette is None:
            palette = rgb.quantize(colors=96, method=Image.Quantize.MEDIANCUT)
            images.append(palette)
        else:
            images.append(rgb.quantize(palette=palette, dither=Image.Dither.NONE))
        progress.advance()
    duration = max(20, int(round(1000.0 / fps)))
    images[0].save(out, save_all=True, append_images=images[1:], duration=duration, loop=0)


def write_mp4(scene, frames, fps, out, progress):
    ffmpeg = shutil.which("ffmpeg")
    if ffmpeg is None:
        raise RenderError(f"{out}: writing MP4 needs ffmpeg, which is not on PATH (install it: apt-get install ffmpeg; "
                          "or write a GIF: --out run.gif)")
    first = scene.draw(frames[0])
    h, w = first.shape[:2]
    cmd = [ffmpeg, "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{w}x{h}", "-r",
           f"{fps:g}", "-i", "-", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p",
           "-movflags", "+faststart", out]
    proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        proc.stdin.write(first.tobytes())
        progress.advance()
        for k in frames[1:]:
            proc.stdin.write(scene.draw(k).tobytes())
            progress.advance()
        proc.stdin.close()
    except BrokenPipeError:
        pass
    err = proc.stderr.read().decode(errors="replace").strip()
    if proc.wait() != 0:
        last = err.splitlines()[-1] if err else f"exit {proc.returncode}"
        raise RenderError(f"{out}: ffmpeg failed: {last}")


FRAME_FORMATS = (".png", ".svg", ".pdf")


def check_output(out, frame, every):
    """The output path's checks, before anything is read or drawn: a file name (not a
    directory) in an existing directory, with an extension the mode can write."""
    ext = os.path.splitext(out)[1].lower()
    if os.path.isdir(out):
        name = "frame.png" if frame is not None else "run.gif"
        raise RenderError(f"--out {out}: is a directory; give a file name such as {os.path.join(out, name)}")
    if frame is not None:
        if ext not in FRAME_FORMATS:
            raise RenderError(f"--out {out}: --frame writes one image as {', '.join(FRAME_FORMATS)}"
                              f" (an animation: drop --frame and use .gif or .mp4)")
        if every is not None:
            raise RenderError("--every applies to animations, not to --frame")
    elif ext not in (".gif", ".mp4"):
        raise RenderError(f"--out {out}: an animation must be .gif or .mp4 (one image: --frame K --out FILE.png)")
    out_dir = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(out_dir):
        raise RenderError(f"--out {out}: the directory {out_dir} does not exist")


def render(path, out, frame=None, every=None, progress=True):
    """Renders `path` to `out` (see the module doc). Returns the number of frames written."""
    check_output(out, frame, every)
    ext = os.path.splitext(out)[1].lower()
    traj = _trajectory.read_trajectory(path)
    if frame is not None and not 0 <= frame <= traj.steps:
        raise RenderError(f"--frame {frame}: {path} has states 0..{traj.steps}")
    import matplotlib.pyplot as plt

    scene = Scene(traj)
    try:
        if frame is not None:
            from PIL import Image

            pixels = scene.draw(frame)
            if ext == ".png":
                Image.fromarray(pixels).save(out, optimize=True)
            else:
                scene.fig.savefig(out, dpi=DPI)
            return 1
        frames, fps = frame_list(traj, every)
        bar = Progress(len(frames), progress)
        (write_gif if ext == ".gif" else write_mp4)(scene, frames, fps, out, bar)
        bar.finish()
        return len(frames)
    finally:
        plt.close(scene.fig)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="deepcontact render", description=__doc__.split("\n\n")[0])
    ap.add_argument("trajectory")
    ap.add_argument("--out", required=True)
    ap.add_argument("--frame", type=int)
    ap.add_argument("--every", type=int)
    ap.add_argument("--no-progress", action="store_true")
    # The caller writes --out under a temporary name and renames it onto this one.
    ap.add_argument("--report-as", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    try:
        n = render(a.trajectory, a.out, frame=a.frame, every=a.every, progress=not a.no_progress)
    except (RenderError, IoError, OSError) as e:
        message = str(e).replace(a.out, a.report_as) if a.report_as else str(e)
        print(f"deepcontact: error: {message}", file=sys.stderr)
        return 1
    print(f"render: {a.report_as or a.out} ({n} frame{'s' if n != 1 else ''})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
