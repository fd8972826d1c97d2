"""Shared fixtures: the `pointillist` command line (the reference the package is compared
with), scene files written from numpy columns, PNG reading."""

import os
import pathlib
import subprocess

import numpy as np
import pytest
from PIL import Image as PILImage

REPO = pathlib.Path(__file__).resolve().parents[3]


def _cli_path():
    """The CLI binary: $POINTILLIST_CLI, else the workspace's release or debug build."""
    env = os.environ.get("POINTILLIST_CLI")
    if env:
        return pathlib.Path(env)
    for profile in ("release", "debug"):
        path = REPO / "target" / profile / "pointillist"
        if path.exists():
            return path
    return None


@pytest.fixture(scope="session")
def cli():
    path = _cli_path()
    if path is None or not path.exists():
        pytest.fail(
            "the pointillist CLI is needed to compare with: build it with "
            "`cargo build -p pointillist-cli` or set POINTILLIST_CLI"
        )
    return path


def read_png(path):
    """An RGBA8 PNG as an (h, w, 4) uint8 array."""
    with PILImage.open(path) as im:
        assert im.mode == "RGBA", im.mode
        return np.asarray(im).copy()


def run_cli(cli, *args):
    """Runs the CLI; returns (exit status, stdout, stderr)."""
    p = subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def render_cli(cli, scene_path, tmp_path):
    """`pointillist render SCENE -o OUT.png`, read back."""
    out = tmp_path / (scene_path.stem + ".png")
    rc, _, err = run_cli(cli, "render", scene_path, "-o", out)
    assert rc == 0, err
    return read_png(out)


def pixel_x(x, lo, hi, pixels):
    """The documented formula, restated: X = (x - lo) * (pixels / (hi - lo)) - 0.5 in float64,
    rounded once to float32."""
    scale = pixels / (hi - lo)
    return ((np.asarray(x, np.float64) - lo) * scale - 0.5).astype(np.float32)


def pixel_y(y, lo, hi, pixels):
    """Y = (hi - y) * (pixels / (hi - lo)) - 0.5: y upwards."""
    scale = pixels / (hi - lo)
    return ((hi - np.asarray(y, np.float64)) * scale - 0.5).astype(np.float32)


# The render states each preset stands for (docs/PYTHON.md), restated for the scene files.
PRESET_STATES = {
    "add": {"ALPHABLENDENABLE": True, "SRCBLEND": "ONE", "DESTBLEND": "ONE", "BLENDOP": "ADD"},
    "alpha": {
        "ALPHABLENDENABLE": True,
        "SRCBLEND": "SRCALPHA",
        "DESTBLEND": "INVSRCALPHA",
        "BLENDOP": "ADD",
    },
    "max": {"ALPHABLENDENABLE": True, "SRCBLEND": "ONE", "DESTBLEND": "ONE", "BLENDOP": "MAX"},
    "replace": {"ALPHABLENDENABLE": False},
}


def _toml(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    return repr(v)


def write_scene(
    tmp_path,
    name,
    X,
    Y,
    *,
    width,
    height,
    blend,
    size=1.0,
    color=0xFFFFFFFF,
    z=None,
    clear=0xFF000000,
    texture=None,
):
    """A scene file drawing pixel positions X, Y (float32) as `pointillist.points` says it
    does: one XYZRHW vertex a point (PSIZE when sizes vary, DIFFUSE), the preset's states,
    POINTSIZE_MIN 0, POINTSIZE_MAX 8192, ZENABLE with depths only, a sprite texture on stage 0 (MODULATE colour
    and alpha, linear filtering, clamped)."""
    n = len(X)
    per_size = np.ndim(size) != 0
    color = np.asarray(color)
    if color.ndim == 2:
        r, g, b, a = (color[:, k].astype(np.uint32) for k in range(4))
        argb = (a << 24) | (r << 16) | (g << 8) | b
    else:
        argb = np.broadcast_to(color.astype(np.uint32), (n,))
    fields = [("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("rhw", "<f4")]
    if per_size:
        fields.append(("psize", "<f4"))
    fields.append(("diffuse", "<u4"))
    v = np.zeros(n, dtype=fields)
    v["x"], v["y"], v["rhw"], v["diffuse"] = X, Y, 1.0, argb
    if z is not None:
        v["z"] = z
    if per_size:
        v["psize"] = size
    (tmp_path / f"{name}.bin").write_bytes(v.tobytes())
    states = dict(
        PRESET_STATES[blend], POINTSIZE_MIN=0.0, POINTSIZE_MAX=8192.0, ZENABLE=z is not None
    )
    if not per_size:
        states["POINTSIZE"] = float(np.float32(size))
    lines = [
        "format = 1",
        "[target]",
        f"width = {width}",
        f"height = {height}",
        f"clear = {clear:#x}",
        "[states]",
    ]
    if texture is not None:
        states["POINTSPRITEENABLE"] = True
    lines += [f"{k} = {_toml(v)}" for k, v in states.items()]
    if texture is not None:
        PILImage.fromarray(texture, "RGBA").save(tmp_path / f"{name}_tex.png")
        lines += [
            "[stage.0]",
            'COLOROP = "MODULATE"',
            'COLORARG1 = "TEXTURE"',
            'COLORARG2 = "CURRENT"',
            'ALPHAOP = "MODULATE"',
            'ALPHAARG1 = "TEXTURE"',
            'ALPHAARG2 = "CURRENT"',
            'MINFILTER = "LINEAR"',
            'MAGFILTER = "LINEAR"',
            'ADDRESSU = "CLAMP"',
            'ADDRESSV = "CLAMP"',
            "[[texture]]",
            "stage = 0",
            f'file = "{name}_tex.png"',
        ]
    fvf = "XYZRHW | PSIZE | DIFFUSE" if per_size else "XYZRHW | DIFFUSE"
    lines += ["[[draw]]", f'fvf = "{fvf}"', f'file = "{name}.bin"']
    path = tmp_path / f"{name}.toml"
    path.write_text("\n".join(lines) + "\n")
    return path
