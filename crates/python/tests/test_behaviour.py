"""Device behaviour switches from Python: `behaviour={name: option}` on every call that makes a
device, over a scene's `[behaviour]` as the CLI's `--behaviour`; `pointillist.behaviours()` is
`pointillist behaviours --json`."""

import json

import numpy as np
import pytest

import pointillist
from conftest import read_png, run_cli

ONE = {"minimum_size": "one_pixel"}
NAMES = (
    "specular_fog, fog_without_specular, minimum_size, fog_start_equals_end, zero_rhw, "
    "point_size_max_default, depth_clip, pretransformed_table_fog, table_fog_depth, "
    "pretransformed_point_scale, xyzw_input_w, light_order, zero_attenuation"
)


def lit(img):
    """The (row, column) of every pixel whose colour is not black."""
    return [tuple(p) for p in np.argwhere(img[..., :3].any(axis=2)).tolist()]


@pytest.mark.parametrize("color", [0xFFFF0000, np.array([0xFFFF0000, 0xFFFF0000], np.uint32)])
def test_points_below_one_pixel_draw_one_under_minimum_size(color):
    # Size 0 at (10.5, 5.5) and 0.5 at (3.5, 7.5): squares covering no pixel centre, so
    # nothing by default; one_pixel draws each as size 1: pixels 10..11 and 3..4. A constant
    # colour is counted, per-point colours go through the device: both see the switch.
    x, y = np.array([10.5, 3.5], np.float32), np.array([5.5, 7.5], np.float32)
    size = np.array([0.0, 0.5], np.float32)
    kw = dict(size=size, color=color, width=20, height=10)
    assert lit(pointillist.points(x, y, **kw)) == []
    assert lit(pointillist.points(x, y, behaviour=None, **kw)) == []
    assert lit(pointillist.points(x, y, behaviour={"minimum_size": "none"}, **kw)) == []
    img = pointillist.points(x, y, behaviour=ONE, **kw)
    assert lit(img) == [(5, 10), (7, 3)]
    assert img[5, 10].tolist() == [255, 0, 0, 255]
    # Switches that do not touch these points change nothing.
    other = {"zero_rhw": "dropped", "specular_fog": "clamped", "minimum_size": "one_pixel"}
    assert np.array_equal(pointillist.points(x, y, behaviour=other, **kw), img)


def test_device_takes_the_switches_and_reports_them():
    v = np.array(
        [((10.5, 5.5, 0.5, 1.0), 0xFF00FF00)], dtype=[("xyzrhw", "<f4", 4), ("diffuse", "<u4")]
    )

    def draw(**kw):
        dev = pointillist.Device(20, 10, **kw)
        dev.set_render_state("POINTSIZE_MIN", 0.0)  # the D3D9 default, 1, would enlarge it
        dev.set_render_state("POINTSIZE", 0.0)
        dev.draw_points("XYZRHW | DIFFUSE", v)
        return dev, dev.read_target()

    dev, img = draw()
    assert lit(img) == []
    assert dev.behaviour["minimum_size"] == "none"
    dev, img = draw(behaviour=ONE)
    assert lit(img) == [(5, 10)] and img[5, 10].tolist() == [0, 255, 0, 255]
    assert dev.behaviour == {
        "specular_fog": "unclamped",
        "fog_without_specular": "fogged",
        "minimum_size": "one_pixel",
        "fog_start_equals_end": "vertex_fogged_table_step",
        "zero_rhw": "drawn",
        "point_size_max_default": "sixty_four",
        "depth_clip": "vertex_processing",
        "pretransformed_table_fog": "projection",
        "table_fog_depth": "viewport",
        "pretransformed_point_scale": "ignored",
        "xyzw_input_w": "ignored",
        "light_order": "lowest_indices",
        "zero_attenuation": "flt_max",
    }


def scene(tmp_path, table="", animation=""):
    """A 16x8 scene of two points: A (size 0, RHW 1) at pixel (3, 2), drawn only under
    minimum_size=one_pixel; B (size 3, RHW 0) around pixel (10, 4), dropped only under
    zero_rhw=dropped. `table` is its [behaviour] table."""
    path = tmp_path / "s.toml"
    path.write_text(
        "format = 1\n[target]\nwidth = 16\nheight = 8\n"
        + animation
        + "[states]\nPOINTSIZE_MIN = 0.0\n"
        + (f"[behaviour]\n{table}\n" if table else "")
        + '[[draw]]\nfvf = "XYZRHW | PSIZE | DIFFUSE"\nvertices = [\n'
        + "  [3.5, 2.5, 0.5, 1.0, 0.0, 0xFFFF0000],\n"
        + "  [10.0, 4.0, 0.5, 0.0, 3.0, 0xFF0000FF],\n]\n"
    )
    return path


A = [(2, 3)]
B = [(r, c) for r in (3, 4, 5) for c in (9, 10, 11)]


@pytest.mark.parametrize(
    "table,behaviour,flags,pixels",
    [
        ("", None, [], B),
        ("", ONE, ["minimum_size=one_pixel"], sorted(A + B)),
        # The argument overrides the scene's table where it names a switch ...
        ('minimum_size = "one_pixel"', {"minimum_size": "none"}, ["minimum_size=none"], B),
        # ... and keeps the scene's other switches.
        ('minimum_size = "one_pixel"', None, [], sorted(A + B)),
        ('minimum_size = "one_pixel"', {"zero_rhw": "dropped"}, ["zero_rhw=dropped"], A),
        (
            'minimum_size = "one_pixel"\nzero_rhw = "dropped"',
            {"zero_rhw": "drawn", "minimum_size": "none"},
            ["zero_rhw=drawn", "minimum_size=none"],
            B,
        ),
    ],
)
def test_render_scene_sets_switches_over_the_scenes_as_the_cli(
    cli, tmp_path, table, behaviour, flags, pixels
):
    path = scene(tmp_path, table)
    got = pointillist.render_scene(path, behaviour=behaviour)
    assert lit(got) == pixels
    out = tmp_path / "cli.png"
    args = [a for f in flags for a in ("--behaviour", f)]
    rc, _, err = run_cli(cli, "render", path, "-o", out, *args)
    assert rc == 0, err
    assert np.array_equal(got, read_png(out))


def test_animate_sets_switches_over_the_scenes_as_the_cli(cli, tmp_path):
    path = scene(tmp_path, 'zero_rhw = "dropped"', "[animation]\nframes = 2\nfps = 10\n")
    behaviour = {"minimum_size": "one_pixel", "zero_rhw": "drawn"}
    py_out, cli_out = tmp_path / "py.png", tmp_path / "cli.png"
    pointillist.animate(path, py_out, behaviour=behaviour)
    rc, _, err = run_cli(
        cli, "animate", path, "-o", cli_out,
        "--behaviour", "minimum_size=one_pixel", "--behaviour", "zero_rhw=drawn",
    )
    assert rc == 0, err
    assert py_out.read_bytes() == cli_out.read_bytes()
    pointillist.animate(path, py_out)
    assert py_out.read_bytes() != cli_out.read_bytes()
    frame = pointillist.render_scene(path, 1, behaviour=behaviour)
    assert lit(frame) == sorted(A + B)


BAD = [
    (
        {"minimum": "one_pixel"},
        ValueError,
        f"behaviour: unknown behaviour `minimum` (expected one of: {NAMES}, or profile)",
    ),
    (
        {"minimum_size": "big"},
        ValueError,
        "behaviour: unknown option `big` of behaviour `minimum_size` (expected one of: none, "
        "one_pixel)",
    ),
    (
        {"minimum_size": " one_pixel"},
        ValueError,
        "behaviour: unknown option ` one_pixel` of behaviour `minimum_size` (expected one of: "
        "none, one_pixel)",
    ),
    ({1: "none"}, TypeError, f"behaviour key 1 is not a str (expected one of: {NAMES}, or profile)"),
    (
        {"profile": "xp"},
        ValueError,
        "behaviour: unknown behaviour profile `xp` (expected one of: windows, warp, d3d9on12, "
        "wine, dxvk)",
    ),
    (
        {"profile": 1},
        TypeError,
        'behaviour["profile"] must be a str (expected one of: windows, warp, d3d9on12, wine, '
        "dxvk); got 1",
    ),
    (
        {"zero_rhw": 0},
        TypeError,
        'behaviour["zero_rhw"] must be a str (expected one of: drawn, dropped); got 0',
    ),
    (
        ["minimum_size=one_pixel"],
        TypeError,
        'behaviour must be a dict of switch names to options, such as {"minimum_size": '
        "\"one_pixel\"}, or None; got ['minimum_size=one_pixel']",
    ),
    (
        "minimum_size=one_pixel",
        TypeError,
        'behaviour must be a dict of switch names to options, such as {"minimum_size": '
        "\"one_pixel\"}, or None; got 'minimum_size=one_pixel'",
    ),
]


@pytest.mark.parametrize("bad,kind,message", BAD)
def test_bad_switches_raise_one_line_naming_the_argument(tmp_path, bad, kind, message):
    path = scene(tmp_path)
    x = np.zeros(1, np.float32)
    calls = [
        lambda: pointillist.points(x, x, width=4, height=4, behaviour=bad),
        lambda: pointillist.Device(4, 4, behaviour=bad),
        lambda: pointillist.render_scene(path, behaviour=bad),
        lambda: pointillist.animate(path, tmp_path / "a.png", behaviour=bad),
    ]
    for call in calls:
        with pytest.raises(kind) as info:
            call()
        assert str(info.value) == message
    assert not (tmp_path / "a.png").exists()


def test_behaviours_is_the_clis_table(cli):
    rc, out, err = run_cli(cli, "behaviours", "--json")
    assert rc == 0, err
    table = pointillist.behaviours()
    assert table == json.loads(out)
    assert [d["name"] for d in table] == NAMES.split(", ")
    minimum = table[2]
    assert minimum["options"] == ["none", "one_pixel"] and minimum["default"] == "none"
    assert minimum["evidence"] == "hardware" and minimum["rule"] == "SPEC 2.5"
    assert set(minimum["option_effects"]) == {"none", "one_pixel"}
    # A copy: changing it changes nothing of the next.
    table[2]["default"] = "one_pixel"
    assert pointillist.behaviours()[2]["default"] == "none"


def test_a_profile_sets_its_switches_first_as_the_cli(cli):
    # d3d9on12 draws sub-pixel points as one pixel (minimum_size = one_pixel); a switch beside
    # it wins whatever the dict's order; behaviour_profiles() is the CLI's --profiles --json.
    x, y = np.array([10.5], np.float32), np.array([5.5], np.float32)
    kw = dict(size=0.0, color=0xFFFF0000, width=20, height=10)
    assert lit(pointillist.points(x, y, behaviour={"profile": "d3d9on12"}, **kw)) == [(5, 10)]
    for order in (
        {"minimum_size": "none", "profile": "d3d9on12"},
        {"profile": "d3d9on12", "minimum_size": "none"},
    ):
        assert lit(pointillist.points(x, y, behaviour=order, **kw)) == []
    dev = pointillist.Device(4, 4, behaviour={"profile": "wine"})
    assert dev.behaviour["depth_clip"] == "clipping_ignored"
    assert dev.behaviour["table_fog_depth"] == "clip_z"
    rc, out, err = run_cli(cli, "behaviours", "--profiles", "--json")
    assert rc == 0, err
    profiles = pointillist.behaviour_profiles()
    assert profiles == json.loads(out)
    assert [p["name"] for p in profiles] == ["windows", "warp", "d3d9on12", "wine", "dxvk"]
    assert profiles[2]["settings"]["minimum_size"] == "one_pixel"
