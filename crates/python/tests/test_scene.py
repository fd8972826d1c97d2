"""`pointillist.render_scene` draws what `pointillist render` draws, and fails with its
message."""

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
    assert issubclass(pointillist.SceneError, pointillist.Error)
