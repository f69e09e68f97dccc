"""`deepcontact render` and the trajectory reader."""
import shutil

import numpy as np
import pytest
from PIL import Image

from conftest import SMALL, cli_error, run_cli, set_args


@pytest.fixture(scope="module")
def run_h5(tmp_path_factory):
    path = tmp_path_factory.mktemp("render") / "run.h5"
    run_cli("simulate", *set_args(SMALL), "--out", path)
    return path


def test_reader_matches_the_world(dc, run_h5):
    t = dc.read_trajectory(run_h5)
    w = dc.World(set=SMALL)
    assert np.array_equal(t.position[0], w.bodies.position)
    for k in range(10):
        w.step(sweeps=SMALL["solver.sweeps"])
        c = t.step_contacts(k)
        assert np.array_equal(c["lambda"], w.contacts["lambda"]) and np.array_equal(c["point"], w.contacts.point)
        assert np.array_equal(t.position[k + 1], w.bodies.position)
    assert t.width == 30.0 and t.walls == ["left", "right", "bottom", "top"] and t.dt == 0.01
    # A circle-only file: no table (format 1) or one of circles only (format 2).
    assert t.shapes is None or all(k == "circle" for k in t.shapes["kind"])
    assert len(t.step_contacts(t.steps)["gap"]) == 0


def test_frame_png(run_h5, tmp_path):
    out = tmp_path / "f.png"
    p = run_cli("render", run_h5, "--frame", 60, "--out", out)
    assert "1 frame" in p.stdout
    im = Image.open(out)
    assert im.size[0] >= 400 and im.size[1] >= 400


def test_gif_has_one_frame_per_every_steps(run_h5, tmp_path):
    out = tmp_path / "r.gif"
    run_cli("render", run_h5, "--out", out, "--every", 10)
    im = Image.open(out)
    assert im.n_frames == SMALL["time.steps"] // 10 + 1  # states 0, 10, …, 80


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="ffmpeg not installed")
def test_mp4(run_h5, tmp_path):
    out = tmp_path / "r.mp4"
    run_cli("render", run_h5, "--out", out, "--every", 20)
    assert out.read_bytes()[4:8] == b"ftyp"


def test_bad_input_gives_one_line(run_h5, tmp_path):
    assert "an animation must be .gif or .mp4" in cli_error("render", run_h5, "--out", tmp_path / "x.png")
    assert "--frame 999" in cli_error("render", run_h5, "--frame", 999, "--out", tmp_path / "x.png")
    missing = tmp_path / "nope.h5"
    assert str(missing) in cli_error("render", missing, "--out", tmp_path / "x.gif")
    assert "ffmpeg" in cli_error_without_ffmpeg(run_h5, tmp_path)


def cli_error_without_ffmpeg(run_h5, tmp_path):
    import os
    import subprocess

    from conftest import CLI

    env = dict(os.environ, PATH="/nonexistent")
    p = subprocess.run([CLI, "render", str(run_h5), "--out", str(tmp_path / "x.mp4")], capture_output=True,
                       text=True, env=env)
    assert p.returncode == 1
    return p.stderr.strip().splitlines()[-1]


def test_render_from_python(dc, run_h5, tmp_path):
    assert dc.render(run_h5, tmp_path / "p.png", frame=5) == 1
    assert min(Image.open(tmp_path / "p.png").size) >= 400
    assert dc.render(run_h5, tmp_path / "p.gif", every=40, progress=False) == 3  # states 0, 40, 80


def test_reference_trajectory_time_includes_the_warm_up(dc, tmp_path):
    from conftest import run_cli, SOURCE

    run_cli("bench", "--scene", SOURCE / "scenes" / "small.toml", "--steps", 30, "--warmup-steps", 12, "--seeds", 1,
            "--warmstarts", "zero", "--out", tmp_path)
    t = dc.read_trajectory(tmp_path / "reference.h5")
    assert t.start_step == 12
    assert t.time(0) == 12 * t.dt  # state 0 of the reference is the world after the warm-up
    assert t.time(t.steps) == 30 * t.dt


def test_world_render_and_trajectory_frame_agree_on_the_time(dc, tmp_path):
    w = dc.World(set={"bodies.count": 8, "bodies.sigma": 2.0})
    for _ in range(7):
        w.step()
    w._write_trajectory(tmp_path / "state.h5")
    t = dc.read_trajectory(tmp_path / "state.h5")
    assert t.steps == 0 and t.start_step == 7 and t.time(0) == w.time
    assert t.frame(0).shape == w.render().shape


def test_frame_label_stays_off_the_scene(dc, run_h5):
    # The label (time, step, contacts) sits above the scene: its box meets neither the walls
    # (the top-left corner of the box) nor anything drawn inside the axes.
    from deepcontact import render_trajectory

    scene = render_trajectory.Scene(dc.read_trajectory(run_h5))
    try:
        scene.draw(5)
        renderer = scene.fig.canvas.get_renderer()
        label = scene.label.get_window_extent(renderer)
        axes = scene.ax.get_window_extent(renderer)
        assert scene.label.get_text().startswith("t =")
        assert label.y0 > axes.y1, (label, axes)  # wholly above the scene's box, walls included
    finally:
        import matplotlib.pyplot as plt

        plt.close(scene.fig)


def test_a_failed_render_keeps_the_earlier_image(dc, run_h5, tmp_path, monkeypatch):
    from deepcontact import render_trajectory

    out = tmp_path / "run.gif"
    out.write_bytes(b"earlier image")

    def fails_half_way(scene, frames, fps, path, progress):
        with open(path, "wb") as f:
            f.write(b"partial")
        raise OSError(f"{path}: No space left on device")

    monkeypatch.setattr(render_trajectory, "write_gif", fails_half_way)
    with pytest.raises(OSError):
        dc.render(run_h5, out, every=20, progress=False)
    assert out.read_bytes() == b"earlier image"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.gif"]
    monkeypatch.undo()
    assert dc.render(run_h5, out, every=20, progress=False) > 1
    assert out.read_bytes()[:6] == b"GIF89a"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.gif"]
