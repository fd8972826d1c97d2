"""`pointillist.render_scene` draws what `pointillist render` draws, and fails with its
message."""

import _thread
import signal
import threading

import numpy as np
import pytest

import pointillist
from conftest import REPO, read_png, run_cli

SCENES = REPO / "scenes"


@pytest.mark.parametrize(
    "name,frame",
    [("ring", None), ("blending", None), ("clip_planes_scaled", None), ("snow", 4)],
)
def test_render_scene_matches_the_cli(cli, tmp_path, name, frame):
    out = tmp_path / "out.png"
    args = ["render", SCENES / f"{name}.toml", "-o", out]
    if frame is not None:
        args += ["--frame", frame]
    rc, _, err = run_cli(cli, *args)
    assert rc == 0, err
    got = pointillist.render_scene(SCENES / f"{name}.toml", frame)
    assert isinstance(got, pointillist.Image)
    assert np.array_equal(got, read_png(out))


def test_scene_errors_carry_the_cli_message(cli, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('format = 1\n[target]\nwidth = 64\nheight = "tall"\n')
    rc, _, err = run_cli(cli, "render", bad, "-o", tmp_path / "x.png")
    assert rc != 0
    line = err.strip().splitlines()[-1]
    assert line.startswith("error: ")
    with pytest.raises(pointillist.SceneError) as info:
        pointillist.render_scene(bad)
    assert str(info.value) == line[len("error: "):]
    assert str(bad) in str(info.value) and ":4:" in str(info.value)
    with pytest.raises(pointillist.SceneError) as info:
        pointillist.render_scene(tmp_path / "missing.toml")
    assert "cannot read scene file" in str(info.value)
    with pytest.raises(pointillist.SceneError, match="frame 99 is outside"):
        pointillist.render_scene(SCENES / "snow.toml", 99)
    with pytest.raises(ValueError) as info:
        pointillist.render_scene(SCENES / "snow.toml", -1)
    assert str(info.value) == "frame -1 is outside 0..=4294967295"
    with pytest.raises(TypeError) as info:
        pointillist.render_scene(None)
    assert str(info.value) == "path must be a path (str or os.PathLike); got None"
    with pytest.raises(TypeError) as info:
        pointillist.render_scene(SCENES / "snow.toml", backend=1)
    assert str(info.value) == 'backend must be a string ("cpu" or "gpu"); got 1'
    assert issubclass(pointillist.SceneError, pointillist.Error)


def test_animate_writes_what_the_cli_writes(cli, tmp_path):
    cli_out, py_out = tmp_path / "cli.png", tmp_path / "py.png"
    rc, _, err = run_cli(cli, "animate", SCENES / "snow.toml", "-o", cli_out, "--frames", 3)
    assert rc == 0, err
    pointillist.animate(SCENES / "snow.toml", py_out, frames=3)
    assert py_out.read_bytes() == cli_out.read_bytes()
    pattern = tmp_path / "seq" / "f_%02d.png"
    pattern.parent.mkdir()
    pointillist.animate(SCENES / "snow.toml", pattern, frames=3)
    assert sorted(p.name for p in pattern.parent.iterdir()) == ["f_00.png", "f_01.png", "f_02.png"]
    for k in range(3):
        assert np.array_equal(read_png(pattern.parent / f"f_{k:02d}.png"),
                              pointillist.render_scene(SCENES / "snow.toml", k))


@pytest.mark.parametrize("case", ["no format", "frame is a folder", "bad scene"])
def test_animate_errors_carry_the_cli_message_and_write_nothing(cli, tmp_path, case):
    scene = SCENES / "snow.toml"
    out = tmp_path / "out" / "anim.png"
    out.parent.mkdir()
    if case == "no format":
        out = out.with_suffix(".txt")
    elif case == "frame is a folder":
        out = out.parent / "f_%d.png"
        (out.parent / "f_1.png").mkdir()
    else:
        scene = tmp_path / "bad.toml"
        scene.write_text('format = 1\n[target]\nwidth = 64\nheight = "tall"\n')
    before = sorted(out.parent.iterdir())
    rc, _, err = run_cli(cli, "animate", scene, "-o", out, "--frames", 3)
    assert rc != 0
    line = err.strip().splitlines()[-1]
    assert line.startswith("error: ")
    with pytest.raises(pointillist.SceneError) as info:
        pointillist.animate(scene, out, frames=3)
    assert str(info.value) == line[len("error: "):]
    assert sorted(out.parent.iterdir()) == before
    for frames in (0, -1, 2**32):
        with pytest.raises(ValueError) as info:
            pointillist.animate(SCENES / "snow.toml", tmp_path / "out" / "a.png", frames=frames)
        assert str(info.value) == f"frames {frames} is outside 1..=4294967295"
    with pytest.raises(TypeError) as info:
        pointillist.animate(SCENES / "snow.toml", tmp_path / "out" / "a.png", frames=1.5)
    assert str(info.value) == "frames must be an integer; got 1.5"


def test_animate_stops_on_ctrl_c_and_writes_nothing(tmp_path):
    out = tmp_path / "long.png"
    # Ctrl-C as Python delivers it with its own handler, whatever a test runner or the shell
    # that started it set (interrupt_main does nothing when SIGINT is ignored).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            pointillist.animate(SCENES / "snow.toml", out, frames=100_000)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    assert list(tmp_path.iterdir()) == []
