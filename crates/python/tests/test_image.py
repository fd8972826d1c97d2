"""The image knows where it is: x_range, y_range and extent agree with the pixels drawn;
matplotlib shows it at its data coordinates with labelled axes; Pillow gets its bytes."""

import matplotlib
import numpy as np
import pandas as pd
import pytest

import pointillist
import pointillist.dask

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

RED, BLUE = 0xFFFF0000, 0xFF0000FF


def test_ranges_and_extent():
    img = pointillist.points([0.5], [2.0], width=40, height=30, x_range=(0, 4),
                             y_range=(1, 2.5))
    assert (img.x_range, img.y_range) == ((0.0, 4.0), (1.0, 2.5))
    assert img.extent == (0.0, 4.0, 1.0, 2.5)
    assert (img.x_name, img.y_name) == (None, None)
    # A copy or a view of the whole image shows the same data; a slice does not.
    assert img.copy().extent == img.extent and img[:, :].extent == img.extent
    part = img[5:10]
    assert part.x_range is None and part.extent == (-0.5, 39.5, 4.5, -0.5)
    assert type(np.asarray(img)) is np.ndarray
    # Pixel coordinates: the pixels' edges, y downwards (matplotlib's own default extent).
    pixels = pointillist.points([3.0], [4.0], width=8, height=6)
    assert pixels.x_range is None and pixels.extent == (-0.5, 7.5, 5.5, -0.5)
    assert pixels[4, 3].tolist() == [255, 255, 255, 255]


def test_extent_locates_every_pixel():
    # Each one-pixel point lights the pixel whose cell of the extent holds its data position.
    rng = np.random.default_rng(4)
    width, height, xr, yr = 50, 40, (-2.0, 3.0), (10.0, 12.0)
    # Data positions at cell centres, plus up to 0.4 of a cell: never on a boundary.
    cols, rows = rng.integers(0, width, 200), rng.integers(0, height, 200)
    fx, fy = rng.uniform(-0.4, 0.4, (2, 200))
    x = xr[0] + (cols + 0.5 + fx) * (xr[1] - xr[0]) / width
    y = yr[1] - (rows + 0.5 + fy) * (yr[1] - yr[0]) / height
    for i in range(200):
        img = pointillist.points(x[i:i + 1], y[i:i + 1], width=width, height=height,
                                 x_range=xr, y_range=yr, color=RED)
        left, right, bottom, top = img.extent
        col = int((x[i] - left) / (right - left) * width)
        row = int((top - y[i]) / (top - bottom) * height)
        lit = np.argwhere(img[..., 0] == 255)
        assert lit.tolist() == [[row, col]], i


def test_imshow_draws_at_data_coordinates():
    # A red square around (1, 11.5) and a blue one around (-1.5, 10.5): matplotlib shows them
    # at those data coordinates (not upside down), whatever the figure's size and margins.
    width, height = 60, 40
    x = pd.Series([1.0, -1.5], name="longitude")
    y = pd.Series([11.5, 10.5], name="latitude")
    img = pointillist.points(x, y, size=9.0, color=np.array([RED, BLUE], np.uint32),
                             width=width, height=height, x_range=(-2, 3), y_range=(10, 12),
                             clear=0xFFFFFFFF, blend="replace")
    assert (img.x_name, img.y_name) == ("longitude", "latitude")
    fig, ax = plt.subplots(figsize=(4, 3), dpi=100)
    try:
        shown = img.imshow(ax)
        assert tuple(shown.get_extent()) == img.extent
        assert (ax.get_xlabel(), ax.get_ylabel()) == ("longitude", "latitude")
        assert ax.get_xlim() == (-2.0, 3.0) and ax.get_ylim() == (10.0, 12.0)
        fig.canvas.draw()
        rgba = np.asarray(fig.canvas.buffer_rgba())
        for (dx, dy), want in (((1.0, 11.5), (255, 0, 0)), ((-1.5, 10.5), (0, 0, 255))):
            px, py = ax.transData.transform((dx, dy))
            got = rgba[int(rgba.shape[0] - py), int(px), :3]
            assert tuple(got) == want, (dx, dy, got)
        # Away from both squares: the clear colour.
        px, py = ax.transData.transform((2.5, 10.2))
        assert tuple(rgba[int(rgba.shape[0] - py), int(px), :3]) == (255, 255, 255)
        img.imshow(ax, xlabel="lon")
        assert ax.get_xlabel() == "lon"
    finally:
        plt.close(fig)


def test_to_pil():
    rng = np.random.default_rng(2)
    x, y = rng.uniform(0, 1, (2, 500))
    img = pointillist.points(x, y, size=3.0, color=rng.integers(0, 2**32, 500, dtype=np.uint32),
                             width=30, height=20, x_range=(0, 1), y_range=(0, 1),
                             blend="alpha")
    pil = img.to_pil()
    assert pil.mode == "RGBA" and pil.size == (30, 20)
    assert np.array_equal(np.asarray(pil), img)
    assert len(np.unique(img.reshape(-1, 4), axis=0)) > 50
    with pytest.raises(ValueError, match=r"^to_pil needs an \(h, w, 4\) uint8 image"):
        img[..., 0].to_pil()


def test_dask_image_knows_its_ranges():
    import dask.dataframe as dd

    pdf = pd.DataFrame({"lon": [0.1, 0.6, 0.9], "lat": [0.2, 0.5, 0.8]})
    df = dd.from_pandas(pdf, npartitions=2, sort=False)
    kw = dict(width=10, height=10, x_range=(0, 1), y_range=(0, 1))
    for blend in ("add", "alpha"):
        img = pointillist.dask.points(df, "lon", "lat", blend=blend, **kw)
        want = pointillist.points(pdf["lon"], pdf["lat"], blend=blend, **kw)
        assert np.array_equal(img, want)
        assert (img.x_range, img.y_range, img.extent) == ((0.0, 1.0), (0.0, 1.0),
                                                          (0.0, 1.0, 0.0, 1.0))
        assert (img.x_name, img.y_name) == ("lon", "lat") == (want.x_name, want.y_name)
