"""`pointillist.Plot`: the plot's arguments checked once, in Rust; frozen; pickled to Dask's
workers unchanged; and the compiled module's stubs."""

import ast
import pathlib
import pickle
import subprocess
import sys

import numpy as np
import pytest

import pointillist
from pointillist import _native

PACKAGE = pathlib.Path(__file__).resolve().parents[1] / "python" / "pointillist"


def texture():
    return np.random.default_rng(5).integers(0, 256, (5, 7, 4), dtype=np.uint8)


def columns(n=2000, seed=3):
    rng = np.random.default_rng(seed)
    x = rng.uniform(-1.2, 1.2, n)
    y = rng.uniform(-1.2, 1.2, n).astype(np.float32)
    size = rng.uniform(0.5, 7.0, n).astype(np.float32)
    color = rng.integers(0, 2**32, n, dtype=np.uint32)
    return x, y, size, color


def test_fields_and_defaults():
    p = pointillist.Plot(40, 30)
    assert (p.width, p.height, p.blend, p.x_range, p.y_range) == (40, 30, "add", None, None)
    assert (p.clear, p.texture, p.backend, p.commutes) == (0xFF000000, None, "cpu", True)
    assert p.behaviour == pointillist.Device(1, 1).behaviour
    q = pointillist.Plot(
        40, 30, blend="alpha", x_range=(0, 2), y_range=(-1, 1.5), clear=0x10203040,
        texture=texture(), behaviour={"minimum_size": "one_pixel"},
    )
    assert (q.blend, q.x_range, q.y_range, q.clear, q.commutes) == (
        "alpha", (0.0, 2.0), (-1.0, 1.5), 0x10203040, False)
    assert q.behaviour["minimum_size"] == "one_pixel"
    assert np.array_equal(q.texture, texture())
    assert repr(q) == (
        "Plot(40, 30, blend='alpha', x_range=(0.0, 2.0), y_range=(-1.0, 1.5), "
        "clear=0x10203040, texture=<7x5 texture>, behaviour={'minimum_size': 'one_pixel'}, "
        "backend='cpu', marker='square', size_units='pixels')"
    )


def test_frozen_and_texture_copied():
    t = texture()
    p = pointillist.Plot(64, 64, x_range=(-1, 1), y_range=(-1, 1), texture=t)
    with pytest.raises(AttributeError):
        p.blend = "max"
    assert not p.texture.flags.writeable
    with pytest.raises(ValueError):
        p.texture[0, 0, 0] = 1
    x, y, size, color = columns()
    before = _native.points(p, x, y, size=size, color=color)
    t[:] = 0  # the caller's array changes; the plot's texture does not
    after = _native.points(p, x, y, size=size, color=color)
    assert np.array_equal(before, after)
    assert len(np.unique(before.reshape(-1, 4), axis=0)) > 100


@pytest.mark.parametrize("blend", ["add", "alpha", "max", "replace"])
def test_pickled_plot_draws_the_same(blend):
    p = pointillist.Plot(
        80, 60, blend=blend, x_range=(-1, 1), y_range=(-1, 1), clear=0xFF203040,
        texture=texture(), behaviour={"profile": "wine", "minimum_size": "one_pixel"},
    )
    q = pickle.loads(pickle.dumps(p))
    assert type(q) is pointillist.Plot
    assert repr(q) == repr(p)
    assert q.behaviour == p.behaviour
    assert np.array_equal(q.texture, p.texture)
    x, y, size, color = columns()
    want = pointillist.points(
        x, y, size=size, color=color, width=80, height=60, blend=blend, x_range=(-1, 1),
        y_range=(-1, 1), clear=0xFF203040, texture=texture(),
        behaviour={"profile": "wine", "minimum_size": "one_pixel"},
    )
    for plot in (p, q):
        got = _native.points(plot, x, y, size=size, color=color)
        assert np.array_equal(got, want)
    assert len(np.unique(want.reshape(-1, 4), axis=0)) > 50


def plot_error(exc, message, *args, **kw):
    with pytest.raises(exc) as info:
        pointillist.Plot(*args, **kw)
    assert str(info.value) == message


def test_bad_arguments_name_the_argument():
    plot_error(pointillist.Error, "render target 20000x8 is outside 1..=16384 per side",
               20000, 8)
    plot_error(pointillist.Error, "render target 8x0 is outside 1..=16384 per side", 8, 0)
    plot_error(TypeError, "width must be an integer; got 1.5", 1.5, 8)
    plot_error(ValueError,
               'unknown blend "over" (expected "add", "alpha", "max" or "replace")',
               8, 8, blend="over")
    plot_error(TypeError, 'blend must be a string ("add", "alpha", "max" or "replace"); got None',
               8, 8, blend=None)
    plot_error(ValueError, "clear 0x100000000 is outside 0..=0xFFFFFFFF (a D3DCOLOR 0xAARRGGBB)",
               8, 8, clear=2**32)
    plot_error(TypeError, "clear must be a D3DCOLOR, an integer 0xAARRGGBB", 8, 8, clear=None)
    with pytest.raises(ValueError, match=r"^x_range"):
        pointillist.Plot(8, 8, x_range=(1, 0))
    with pytest.raises(ValueError, match=r"^y_range"):
        pointillist.Plot(8, 8, y_range=(2, 2))
    plot_error(ValueError, "x_range must be None or two numbers (lo, hi)", 8, 8, x_range=(1,))
    with pytest.raises(ValueError, match=r"^texture must be an \(height, width, 4\) uint8"):
        pointillist.Plot(8, 8, texture=np.zeros((4, 4, 3), np.uint8))
    with pytest.raises(ValueError, match=r"^behaviour: unknown behaviour `size`"):
        pointillist.Plot(8, 8, behaviour={"size": "1"})
    plot_error(ValueError, 'unknown backend `tpu` (expected "cpu" or "gpu")', 8, 8,
               backend="tpu")


def test_dask_restates_no_rule():
    # The blends and the target's limit are checked by Plot, not listed again in Python.
    tree = ast.parse((PACKAGE / "dask.py").read_text())
    docstrings = {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(node, (ast.Module, ast.FunctionDef)) and ast.get_docstring(node)
    }
    constants = {
        node.value
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant) and id(node) not in docstrings
    }
    # ("add" is the default of the `blend` parameter.)
    for restated in (16384, "alpha", "max", "replace"):
        assert restated not in constants, restated


def stub_names(tree):
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
    return names


def test_stubs_cover_the_compiled_module():
    # The stub names every function and class of _native, and nothing it lacks; the package's
    # .py files carry their own annotations (no .pyi repeats them).
    tree = ast.parse((PACKAGE / "_native.pyi").read_text())
    compiled = {n for n in dir(_native) if not n.startswith("__")}
    assert stub_names(tree) == compiled
    assert sorted(p.name for p in PACKAGE.glob("*.pyi")) == ["_native.pyi"]
    for cls in tree.body:
        if isinstance(cls, ast.ClassDef) and cls.name in ("Plot", "Device"):
            members = {n.name for n in cls.body if isinstance(n, ast.FunctionDef)}
            real = {n for n in dir(getattr(_native, cls.name)) if not n.startswith("_")}
            assert real <= members, (cls.name, real - members)
    init = ast.parse((PACKAGE / "__init__.py").read_text())
    points = next(n for n in init.body if isinstance(n, ast.FunctionDef) and n.name == "points")
    assert points.returns is not None
    assert all(a.annotation is not None for a in points.args.args + points.args.kwonlyargs)


def test_stubs_and_annotations_type_check(tmp_path):
    # mypy's stubtest compares _native.pyi with the installed compiled module (every name,
    # signature and default), and mypy checks the package's inline annotations against it.
    def run(*args):
        done = subprocess.run(
            [sys.executable, "-m", *args], cwd=tmp_path, capture_output=True, text=True
        )
        assert done.returncode == 0, done.stdout + done.stderr

    run("mypy.stubtest", "--mypy-config-file", "/dev/null", "pointillist._native")
    run("mypy", "--cache-dir", str(tmp_path / "cache"), "--ignore-missing-imports",
        "-p", "pointillist")
