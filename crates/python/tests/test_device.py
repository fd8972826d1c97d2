"""`pointillist.Device`: the D3D9 calls from Python give the pixels of the same calls in a scene
file drawn by the CLI; refused calls raise with the device's message."""

import numpy as np
import pytest

import pointillist
from conftest import render_cli

VERTEX = np.dtype(
    [("pos", "<f4", 3), ("psize", "<f4"), ("diffuse", "<u4"), ("uv", "<f4", 2)]
)

SCENE = """\
format = 1
[target]
width = 96
height = 64
clear = 0xFF101820
[transform]
view = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0.25, 0, 5, 1]]
projection = [[1.3, 0, 0, 0], [0, 1.95, 0, 0], [0, 0, 1.02, 1], [0, 0, -1.02, 0]]
[states]
POINTSCALEENABLE = true
POINTSCALE_A = 0.0
POINTSCALE_B = 0.0
POINTSCALE_C = 1.0
POINTSPRITEENABLE = true
ALPHABLENDENABLE = true
SRCBLEND = "SRCALPHA"
DESTBLEND = "INVSRCALPHA"
LIGHTING = false
[stage.0]
COLOROP = "MODULATE"
ALPHAOP = "MODULATE"
MINFILTER = "LINEAR"
MAGFILTER = "LINEAR"
ADDRESSU = "MIRROR"
[[texture]]
stage = 0
width = 2
height = 2
texels = [0xFFFF0000, 0x8000FF00, 0x400000FF, 0xFFFFFFFF]
[viewport]
x = 4
y = 2
width = 88
height = 60
[[clip_plane]]
index = 0
plane = [1.0, 0.0, 0.0, 0.6]
[[draw]]
states = {{ CLIPPLANEENABLE = 1 }}
fvf = "XYZ | PSIZE | DIFFUSE | TEX1"
file = "{bin}"
"""


def vertices(n=400):
    rng = np.random.default_rng(4)
    v = np.zeros(n, VERTEX)
    v["pos"] = rng.uniform(-2, 2, (n, 3)).astype(np.float32)
    v["psize"] = rng.uniform(0.05, 0.6, n)
    v["diffuse"] = rng.integers(0, 2**32, n, dtype=np.uint32)
    v["uv"] = rng.uniform(0, 1, (n, 2))
    return v


def device_like_scene(v):
    dev = pointillist.Device(96, 64, clear=0xFF101820)
    view = np.eye(4, dtype=np.float32)
    view[3] = (0.25, 0, 5, 1)
    dev.set_transform("view", view)
    proj = [[1.3, 0, 0, 0], [0, 1.95, 0, 0], [0, 0, 1.02, 1], [0, 0, -1.02, 0]]
    dev.set_transform("D3DTS_PROJECTION", proj)
    for name, value in [
        ("POINTSCALEENABLE", True),
        ("POINTSCALE_A", 0.0),
        ("POINTSCALE_B", 0),
        ("pointscale_c", 1.0),
        ("D3DRS_POINTSPRITEENABLE", True),
        ("ALPHABLENDENABLE", True),
        ("SRCBLEND", "SRCALPHA"),
        ("DESTBLEND", "INVSRCALPHA"),
        ("LIGHTING", False),
    ]:
        dev.set_render_state(name, value)
    dev.set_texture_stage_state(0, "COLOROP", "MODULATE")
    dev.set_texture_stage_state(0, "D3DTSS_ALPHAOP", "MODULATE")
    dev.set_sampler_state(0, "MINFILTER", "LINEAR")
    dev.set_sampler_state(0, "MAGFILTER", "LINEAR")
    dev.set_sampler_state(0, "ADDRESSU", "MIRROR")
    texels = np.array(
        [[[255, 0, 0, 255], [0, 255, 0, 128]], [[0, 0, 255, 64], [255, 255, 255, 255]]],
        np.uint8,
    )
    dev.set_texture(0, texels)
    dev.set_viewport(4, 2, 88, 60)
    dev.set_clip_plane(0, (1.0, 0.0, 0.0, 0.6))
    dev.set_render_state("CLIPPLANEENABLE", 1)
    return dev


def test_device_calls_match_the_cli(cli, tmp_path):
    v = vertices()
    (tmp_path / "v.bin").write_bytes(v.tobytes())
    (tmp_path / "scene.toml").write_text(SCENE.format(bin="v.bin"))
    want = render_cli(cli, tmp_path / "scene.toml", tmp_path)
    for payload in (v, v.tobytes(), bytearray(v.tobytes()), v.view(np.uint8)):
        dev = device_like_scene(v)
        dev.draw_points("XYZ | PSIZE | DIFFUSE | TEX1", payload)
        got = dev.read_target()
        assert got.shape == (64, 96, 4)
        assert np.array_equal(got, want)
    assert len(np.unique(want.reshape(-1, 4), axis=0)) > 30
    # LIGHTING affects points (SPEC 8): no notice for it; DITHERENABLE still has no effect.
    assert dev.take_notices() == []
    dev.set_render_state("DITHERENABLE", True)
    assert dev.take_notices() == ["render state DITHERENABLE has no effect on points; ignored"]


def test_the_fvf_may_be_a_code():
    v = np.zeros(1, [("xyzrhw", "<f4", 4), ("diffuse", "<u4")])
    v["xyzrhw"] = (2.0, 1.0, 0.5, 1.0)
    v["diffuse"] = 0xFF00FF00
    dev = pointillist.Device(4, 3)
    dev.draw_points(0x004 | 0x040, v)  # D3DFVF_XYZRHW | D3DFVF_DIFFUSE
    img = dev.read_target()
    assert img[1, 2].tolist() == [0, 255, 0, 255]
    assert img[1, 1].tolist() == [0, 0, 0, 255]
    dev.clear(0x00000000)
    assert dev.read_target().sum() == 0
    assert dev.render_state("POINTSIZE") == 0x3F800000
    assert dev.size == (4, 3)


def test_refused_calls_raise_the_device_message():
    dev = pointillist.Device(16, 16)
    cases = [
        (lambda: dev.set_viewport(8, 8, 9, 4), pointillist.Error,
         "invalid viewport: 9x4 at (8, 8) does not fit the 16x16 target"),
        (lambda: dev.set_texture_stage_state(8, "COLOROP", "MODULATE"), pointillist.Error,
         "stage 8 is outside 0..=7"),
        (lambda: dev.set_clip_plane(6, (0, 0, 0, 0)), pointillist.Error,
         "clip plane 6 is outside 0..=5"),
        (lambda: dev.draw_points("XYZRHW | DIFFUSE", b"\0" * 21), pointillist.Error,
         "vertex buffer of 21 bytes is not a multiple of the FVF stride 20"),
        (lambda: dev.draw_points("XYZRHW | BOGUS", b""), ValueError, None),
        (lambda: dev.set_render_state("POINTSIZZLE", 1.0), ValueError,
         "unknown render state `POINTSIZZLE`"),
        (lambda: dev.set_render_state("SRCBLEND", "SOMETIMES"), ValueError, None),
        (lambda: dev.set_render_state("POINTSIZE", "big"), TypeError,
         "POINTSIZE takes a number; got 'big'"),
        (lambda: dev.set_render_state("ALPHABLENDENABLE", 1.0), TypeError,
         "ALPHABLENDENABLE takes True or False; got 1.0"),
        (lambda: dev.set_transform("model", np.eye(4)), ValueError,
         'unknown transform `model` (expected "world", "view" or "projection")'),
        (lambda: dev.set_transform("world", np.eye(3)), ValueError,
         "world matrix must be 4x4; got shape (3, 3)"),
        (lambda: dev.set_texture(0, np.zeros((0, 4, 4), np.uint8)), ValueError,
         "texture: texture size 4x0 has a zero dimension"),
        (lambda: dev.draw_points("XYZRHW | DIFFUSE", np.zeros(2, [("a", "<f4", 6)])),
         ValueError, "vertices have 24-byte rows but the FVF's vertices are 20 bytes"),
        (lambda: dev.draw_points("XYZRHW | DIFFUSE", np.zeros((4, 10), np.uint8)[:, :5]),
         TypeError, None),
        (lambda: pointillist.Device(0, 5), pointillist.Error,
         "render target 0x5 is outside 1..=16384 per side"),
        (lambda: pointillist.Device(5, 5, caps="voodoo"), ValueError, None),
        # Any integer, whatever its sign or size, and other types: one line naming the argument.
        (lambda: pointillist.Device(-1, 5), pointillist.Error,
         "render target -1x5 is outside 1..=16384 per side"),
        (lambda: pointillist.Device(2**64, 5), pointillist.Error,
         "render target 18446744073709551616x5 is outside 1..=16384 per side"),
        (lambda: pointillist.Device(5.0, 5), TypeError, "width must be an integer; got 5.0"),
        (lambda: pointillist.Device(5, 5, backend=None, api=1), TypeError,
         "api must be a string; got 1"),
        (lambda: dev.set_texture_stage_state(-1, "COLOROP", "MODULATE"), pointillist.Error,
         "stage -1 is outside 0..=7"),
        (lambda: dev.set_sampler_state(2**64, "MINFILTER", "LINEAR"), pointillist.Error,
         "sampler 18446744073709551616 is outside 0..=7"),
        (lambda: dev.set_texture(-3, None), pointillist.Error, "stage -3 is outside 0..=7"),
        (lambda: dev.set_clip_plane(-1, (0, 0, 0, 0)), pointillist.Error,
         "clip plane -1 is outside 0..=5"),
        (lambda: dev.set_clip_plane(0, (0, 0, 0)), TypeError,
         "plane must be four numbers (a, b, c, d); got (0, 0, 0)"),
        (lambda: dev.set_viewport(-1, 0, 4, 4), ValueError, "x -1 is outside 0..=4294967295"),
        (lambda: dev.set_viewport(0, 0, 4, 2**32), ValueError,
         "height 4294967296 is outside 0..=4294967295"),
        (lambda: dev.set_viewport(0, 0, 4, 4, min_z="near"), TypeError,
         "min_z must be a number; got 'near'"),
        (lambda: dev.clear(0, depth="far"), TypeError, "depth must be a number; got 'far'"),
        (lambda: dev.set_render_state(None, 1), TypeError,
         "name must be a state's name (a string); got None"),
        (lambda: dev.set_render_state("ZFUNC", -1), ValueError,
         "ZFUNC -0x1 is outside 0..=0xFFFFFFFF (a 32-bit enum value)"),
        (lambda: dev.set_render_state("COLORWRITEENABLE", 2**32), ValueError,
         "COLORWRITEENABLE 0x100000000 is outside 0..=0xFFFFFFFF (a 32-bit value)"),
        (lambda: dev.set_texture_stage_state(0, "COLORARG1", -2), ValueError,
         "COLORARG1 -0x2 is outside 0..=0xFFFFFFFF (a 32-bit texture argument)"),
        (lambda: dev.draw_points(-1, b""), ValueError,
         "fvf -0x1 is outside 0..=0xFFFFFFFF (a D3DFVF code)"),
        (lambda: dev.draw_points(None, b""), TypeError,
         'fvf must be a D3DFVF code (an integer) or names ("XYZRHW | DIFFUSE")'),
        (lambda: dev.set_transform(None, np.eye(4)), TypeError,
         'name must be a string ("world", "view" or "projection"); got None'),
        (lambda: dev.set_transform("world", "eye"), TypeError,
         "world matrix must be 4x4 numbers; got 'eye'"),
    ]
    for call, exc, message in cases:
        with pytest.raises(exc) as info:
            call()
        assert "\n" not in str(info.value)
        if message is not None:
            assert str(info.value) == message
