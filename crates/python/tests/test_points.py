"""`pointillist.points` against the CLI drawing the same points from a scene file, bit for bit;
inputs read in place; the GIL released while drawing; the picture Jupyter shows."""

import io
import threading
import time
import tracemalloc

import numpy as np
import pytest
from PIL import Image as PILImage

import pointillist
from conftest import pixel_x, pixel_y, render_cli, write_scene

W, H = 97, 61
RANGE_X, RANGE_Y = (-1.5, 2.5), (10.0, 13.0)


def data(n, seed):
    """`n` points in data units, some outside the ranges (squares hanging over the edges),
    fractional sizes, colours of every alpha, depths in 0..1 (a few outside, clipped)."""
    rng = np.random.default_rng(seed)
    x = rng.uniform(-1.7, 2.7, n)
    y = rng.uniform(9.8, 13.2, n).astype(np.float32)
    size = rng.uniform(0.0, 9.0, n).astype(np.float32)
    argb = rng.integers(0, 2**32, n, dtype=np.uint32)
    rgba = rng.integers(0, 256, (n, 4), dtype=np.uint8)
    z = rng.uniform(-0.05, 1.05, n).astype(np.float32)
    return x, y, size, argb, rgba, z


def texture():
    rng = np.random.default_rng(99)
    return rng.integers(0, 256, (5, 7, 4), dtype=np.uint8)


CASES = [
    # blend, per-point size, colour kind, depth, texture
    ("add", False, "const", False, False),
    ("add", True, "argb", False, True),
    ("alpha", True, "rgba", False, False),
    ("alpha", True, "argb", True, True),
    ("max", True, "rgba", False, False),
    ("replace", False, "argb", True, False),
    ("replace", True, "rgba", False, True),
]


@pytest.mark.parametrize("blend,per_size,colors,depth,textured", CASES)
def test_points_match_the_cli_drawing_the_same_scene(
    cli, tmp_path, blend, per_size, colors, depth, textured
):
    seed = CASES.index((blend, per_size, colors, depth, textured))
    # Additive points get dim colours, so that the picture does not saturate to white.
    x, y, size, argb, rgba, z = data(20_000, seed)
    if blend == "add":
        argb, rgba = argb & 0x0F0F0F0F, rgba // 16
    size_arg = size if per_size else 3.25
    color = {"const": 0x08060402, "argb": argb, "rgba": rgba}[colors]
    tex = texture() if textured else None
    got = pointillist.points(
        x,
        y,
        size=size_arg,
        color=color,
        z=z if depth else None,
        width=W,
        height=H,
        blend=blend,
        x_range=RANGE_X,
        y_range=RANGE_Y,
        clear=0xFF203040,
        texture=tex,
    )
    scene = write_scene(
        tmp_path,
        "points",
        pixel_x(x, *RANGE_X, W),
        pixel_y(y, *RANGE_Y, H),
        width=W,
        height=H,
        blend=blend,
        size=size_arg,
        color=color,
        z=z if depth else None,
        clear=0xFF203040,
        texture=tex,
    )
    want = render_cli(cli, scene, tmp_path)
    assert got.shape == (H, W, 4) and got.dtype == np.uint8
    assert np.array_equal(got, want)
    assert len(np.unique(want.reshape(-1, 4), axis=0)) > 20, "a picture, not a blank"


def test_more_points_than_one_block_match_the_cli(cli, tmp_path):
    """300 000 points: the package draws them in blocks of 262 144, the scene in one draw."""
    rng = np.random.default_rng(3)
    n = 300_000
    X = rng.uniform(-2, 130, n).astype(np.float32)
    Y = rng.uniform(-2, 66, n).astype(np.float32)
    size = rng.uniform(0.5, 3.0, n).astype(np.float32)
    color = rng.integers(0, 2**32, n, dtype=np.uint32)
    got = pointillist.points(X, Y, size=size, color=color, width=128, height=64, blend="alpha")
    scene = write_scene(
        tmp_path, "block", X, Y, width=128, height=64, blend="alpha", size=size, color=color
    )
    assert np.array_equal(got, render_cli(cli, scene, tmp_path))


def test_pixel_coordinates_without_ranges():
    # SPEC 4.1: size 3 at 4.0 covers 3..5; size 1 at 1.5 covers pixel 1 ([1, 2)).
    img = pointillist.points(
        np.array([4.0, 1.5]), np.array([2.0, 0.5]), size=np.array([3.0, 1.0]),
        width=8, height=5, clear=0,
    )
    lit = np.argwhere(img[..., 3] > 0).tolist()
    assert lit == [[0, 1]] + [[j, i] for j in (1, 2, 3) for i in (3, 4, 5)]


def test_every_input_dtype_gives_the_same_pixels():
    rng = np.random.default_rng(5)
    x = rng.uniform(0, 40, 500).round()
    y = rng.uniform(0, 30, 500).round()
    want = pointillist.points(x.astype(np.float32), y.astype(np.float32), width=40, height=30)
    for dtype in (np.float64, np.int32, np.int64, np.uint16, np.float16):
        got = pointillist.points(x.astype(dtype), y.astype(dtype), width=40, height=30)
        assert np.array_equal(got, want), dtype
    assert np.array_equal(pointillist.points(list(x), tuple(y), width=40, height=30), want)
    # Unaligned float32 (as pickled buffers arrive on a Dask worker) is converted once.
    raw = bytearray(1 + 4 * 500)
    unaligned = np.frombuffer(raw, np.float32, count=500, offset=1)
    unaligned[:] = x
    assert not unaligned.flags.aligned
    assert np.array_equal(pointillist.points(unaligned, y, width=40, height=30), want)
    colors = rng.integers(0, 2**32, 500, dtype=np.uint32)
    a = pointillist.points(x, y, color=colors, width=40, height=30, blend="alpha")
    b = pointillist.points(x, y, color=colors.astype(np.int64), width=40, height=30, blend="alpha")
    rgba = np.stack([(colors >> s & 0xFF).astype(np.uint8) for s in (16, 8, 0, 24)], axis=1)
    c = pointillist.points(x, y, color=rgba, width=40, height=30, blend="alpha")
    assert np.array_equal(a, b) and np.array_equal(a, c)


def traced_peak(fn):
    """The peak of the memory numpy (and Python) allocates while `fn` runs."""
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_contiguous_float32_and_uint32_inputs_are_read_in_place():
    n = 2_000_000
    rng = np.random.default_rng(8)
    x = rng.uniform(0, 64, n).astype(np.float32)
    y = rng.uniform(0, 64, n).astype(np.float32)
    size = np.full(n, 1.5, np.float32)
    argb = rng.integers(0, 2**32, n, dtype=np.uint32)
    rgba = rng.integers(0, 256, (n, 4), dtype=np.uint8)
    z = rng.uniform(0, 1, n).astype(np.float32)

    def draw(**kw):
        return lambda: pointillist.points(width=64, height=64, **kw)

    copy = n * 4  # what a copy of one float32 column would take
    in_place = [
        dict(x=x, y=y),
        dict(x=x, y=y, size=size, color=argb, z=z),
        dict(x=x, y=y, color=rgba),
        dict(x=x.astype(np.float64), y=y.astype(np.float64)),
    ]
    for kw in in_place[:3]:
        assert traced_peak(draw(**kw)) < copy / 8
    x64, y64 = in_place[3]["x"], in_place[3]["y"]
    assert traced_peak(draw(x=x64, y=y64)) < copy / 8
    # The measure sees copies: a strided view, float16 and int64 colours are converted once.
    assert traced_peak(draw(x=x[::2], y=y[::2])) >= copy // 2
    x16 = x.astype(np.float16)
    assert traced_peak(draw(x=x16, y=y)) >= n * 8
    argb64 = argb.astype(np.int64)
    assert traced_peak(draw(x=x, y=y, color=argb64)) >= n * 4


def test_the_gil_is_released_while_drawing():
    n = 4_000_000
    rng = np.random.default_rng(2)
    x = rng.uniform(0, 500, n).astype(np.float32)
    y = rng.uniform(0, 500, n).astype(np.float32)
    ticks = []
    running = threading.Event()
    stop = threading.Event()

    def count():
        running.set()
        while not stop.is_set():
            ticks.append(time.perf_counter())

    t = threading.Thread(target=count)
    t.start()
    running.wait()
    start = time.perf_counter()
    pointillist.points(x, y, size=2.0, width=500, height=500, blend="alpha")
    end = time.perf_counter()
    stop.set()
    t.join()
    during = [s for s in ticks if start < s < end]
    # With the GIL held the counting thread could not run at all inside the call.
    assert len(during) > 1000, (len(during), end - start)


def test_images_show_as_png_in_jupyter():
    img = pointillist.points(
        np.array([2.0]), np.array([1.0]), size=3.0, color=0x80FF0000, width=5, height=4
    )
    assert isinstance(img, pointillist.Image) and isinstance(img, np.ndarray)
    png = img._repr_png_()
    assert png.startswith(b"\x89PNG")
    with PILImage.open(io.BytesIO(png)) as im:
        assert np.array_equal(np.asarray(im), img)
    assert img[..., 0]._repr_png_() is None  # one channel is not an image: the text repr shows
