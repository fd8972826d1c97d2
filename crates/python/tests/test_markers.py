"""`marker="circle"` (an antialiased disc sprite) and `size_units="data"` (sizes in x's data
units): real pixels, the matplotlib conversion the docs give, errors naming the argument,
pickling."""

import pickle

import numpy as np
import pandas as pd
import pytest

import pointillist

W = H = 64


def one(blend="alpha", size=40.0, **kw):
    """One white point of side `size` at the centre of a 64x64 black target."""
    return pointillist.points(
        np.array([31.5]), np.array([31.5]), size=size, width=W, height=H, blend=blend, **kw
    )


@pytest.mark.parametrize("blend", ["add", "alpha", "max", "replace"])
def test_a_circle_is_a_disc_inside_the_square(blend):
    img = one(blend, marker="circle")
    red = np.asarray(img)[..., 0].astype(int)
    assert red[32, 32] == 255, "the centre is the point's colour"
    assert red[13, 13] == 0 and red[50, 50] == 0, "the square's corners are the clear colour"
    assert red[14, 31] == 255, "inside the disc near its top"
    covered = red > 0
    square = np.asarray(one(blend))[..., 0] > 0
    assert covered.sum() < square.sum(), "the disc covers less than the square"
    share = red.sum() / 255 / square.sum()
    assert abs(share - np.pi / 4) < 0.02, f"a disc covers pi / 4 of its square, not {share}"
    assert (red == red[:, ::-1]).all() and (red == red[::-1, :]).all() and (red == red.T).all()
    partial = ((red > 0) & (red < 255)).sum()
    if blend == "replace":
        assert partial == 0, "the alpha test keeps whole texels"
    else:
        assert partial > 40, "an antialiased edge"


def test_a_small_circle_is_smooth_not_a_sampled_cross():
    """A 4-pixel circle samples the disc's mip chain: its corner pixels show part of the
    colour (the disc's coverage averaged), less than its middle ones. (Sprite coordinates run
    from the square's left edge at pixel centres, SPEC 4.3, so a sprite whose edges do not
    fall half-way between pixel centres, such as 3 pixels at x.5, is not mirror-symmetric.)"""
    red = np.asarray(one("alpha", size=4.0, marker="circle"))[..., 0].astype(int)
    block = red[30:34, 30:34]
    assert red.sum() == block.sum(), "the 4x4 pixels of the square"
    corners = [block[0, 0], block[0, 3], block[3, 0], block[3, 3]]
    middle = block[1:3, 1:3]
    assert (block == block[::-1, :]).all() and (block == block.T).all()
    assert 0 < min(corners) and max(corners) < middle.min(), block


def test_data_units_scale_sizes_by_the_x_range():
    """Size 10 on a 0..16 range across 64 pixels is a 40-pixel point, constant or per point,
    square or circle."""
    kw = dict(width=W, height=H, x_range=(0, 16), y_range=(0, 16), blend="add")
    for marker in ("square", "circle"):
        want = one("add", marker=marker)
        got = pointillist.points(
            np.array([8.0]), np.array([8.0]), size=10.0, size_units="data", marker=marker, **kw
        )
        assert np.array_equal(got, want), marker
        per_point = pointillist.points(
            np.array([8.0, 8.0]), np.array([8.0, 8.0]), size=np.array([10.0, 2.0]),
            size_units="data", marker=marker, blend="max", **{k: v for k, v in kw.items()
                                                              if k != "blend"},
        )
        big = np.asarray(per_point)[..., 0] > 0
        assert big.sum() == (np.asarray(want)[..., 0] > 0).sum(), marker


def test_matplotlib_scatter_sizes_convert_as_documented():
    """matplotlib's `s` is an area in points squared: a square marker of s = (72 * 20 / dpi)^2
    at `dpi` is 20 pixels wide, as `size = sqrt(s) * dpi / 72` says."""
    plt = pytest.importorskip("matplotlib.pyplot")
    dpi = 100
    s = (72 * 20 / dpi) ** 2
    fig = plt.figure(figsize=(W / dpi, H / dpi), dpi=dpi)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(-0.5, W - 0.5)
    ax.set_ylim(H - 0.5, -0.5)
    ax.axis("off")
    ax.scatter([31.5], [31.5], s=s, marker="s", c="white", linewidths=0, antialiased=False)
    fig.set_facecolor("black")
    fig.canvas.draw()
    mpl = np.asarray(fig.canvas.buffer_rgba())[..., 0] > 127
    plt.close(fig)
    ours = np.asarray(one("add", size=np.sqrt(s) * dpi / 72))[..., 0] > 127
    cols = np.flatnonzero(ours.any(axis=0))
    mpl_cols = np.flatnonzero(mpl.any(axis=0))
    assert len(cols) == 20
    assert abs(len(mpl_cols) - len(cols)) <= 1, (len(mpl_cols), len(cols))


def test_a_frame_draws_circles_by_column_names():
    rng = np.random.default_rng(4)
    df = pd.DataFrame({"a": rng.uniform(0, 1, 500), "b": rng.uniform(0, 1, 500),
                       "s": rng.uniform(0.01, 0.05, 500)})
    kw = dict(width=W, height=H, x_range=(0, 1), y_range=(0, 1), marker="circle",
              size_units="data", blend="alpha")
    by_name = pointillist.points(df, x="a", y="b", size="s", **kw)
    by_array = pointillist.points(df["a"].to_numpy(), df["b"].to_numpy(),
                                  size=df["s"].to_numpy(), **kw)
    assert np.array_equal(by_name, by_array)
    assert (np.asarray(by_name)[..., 0] > 0).sum() > 500


@pytest.mark.parametrize(
    "kw, words",
    [
        (dict(marker="disc"), ["marker", "disc"]),
        (dict(marker=3), ["marker"]),
        (dict(size_units="points"), ["size_units", "points"]),
        (dict(size_units="data"), ["size_units", "x_range"]),
        (dict(marker="circle", texture=np.zeros((2, 2, 4), np.uint8)), ["circle", "texture"]),
    ],
)
def test_bad_markers_and_units_name_the_argument(kw, words):
    with pytest.raises((ValueError, TypeError)) as info:
        one(**kw)
    for w in words:
        assert w in str(info.value), str(info.value)


def test_a_circle_is_not_shaded_by_counts():
    with pytest.raises(ValueError, match="only a draw of one colour is shaded"):
        one("add", marker="circle", cmap="viridis")


def test_the_plot_keeps_and_pickles_marker_and_units():
    plot = pointillist.Plot(8, 8, x_range=(0, 1), y_range=(0, 1), marker="circle",
                            size_units="data")
    assert (plot.marker, plot.size_units) == ("circle", "data")
    again = pickle.loads(pickle.dumps(plot))
    assert (again.marker, again.size_units) == ("circle", "data")
    assert "marker='circle'" in repr(plot) and "size_units='data'" in repr(again)
    default = pointillist.Plot(8, 8)
    assert (default.marker, default.size_units) == ("square", "pixels")


@pytest.mark.parametrize("kind", ["pandas", "polars"])
def test_frames_draw_colormapped_circles_by_column_names(kind):
    """The issue's picture: a pandas and a polars frame drawn by column names with a colormap
    and round markers sized in data units, each the same as the arrays' draw."""
    rng = np.random.default_rng(11)
    cols = {"lon": rng.uniform(0, 1, 800), "lat": rng.uniform(0, 1, 800),
            "r": rng.uniform(0.01, 0.04, 800), "v": rng.normal(0, 1, 800)}
    if kind == "polars":
        frame = pytest.importorskip("polars").DataFrame(cols)
    else:
        frame = pd.DataFrame(cols)
    kw = dict(width=W, height=H, x_range=(0, 1), y_range=(0, 1), marker="circle",
              size_units="data", blend="alpha", cmap="viridis", how="eq_hist")
    got = pointillist.points(frame, x="lon", y="lat", size="r", color="v", **kw)
    want = pointillist.points(cols["lon"], cols["lat"], size=cols["r"], color=cols["v"], **kw)
    assert np.array_equal(got, want)
    rgb = np.asarray(got)[..., :3].reshape(-1, 3)
    assert len(np.unique(rgb, axis=0)) > 50, "colours from the colormap, blended edges"
    assert got.extent == (0, 1, 0, 1)
