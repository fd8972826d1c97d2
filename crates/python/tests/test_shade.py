"""Colour from values (issue 34 item 3): `cmap`, `how`, `vmin`/`vmax`, `color_key`, and counted
draws shaded from their counts; each point drawn on a pixel of its own (pixel coordinates,
one-pixel points) so that every colour is read back and checked against numbers computed here
or by matplotlib."""

import sys

import numpy as np
import pytest

import pointillist

W, H = 8, 4


def draw(values, **kw):
    """Points 0..n-1 on pixels (i % W, i // W), "replace": each pixel shows its point."""
    n = len(values)
    i = np.arange(n)
    kw = dict(dict(width=W, height=H, blend="replace"), **kw)
    return pointillist.points((i % W).astype(np.float32), (i // W).astype(np.float32),
                              color=values, **kw)


def colours(img, n):
    """The RGBA of pixels 0..n-1, row by row."""
    return img.reshape(-1, 4)[:n]


def grey(levels):
    return np.array([[v, v, v, 255] for v in levels], dtype=np.uint8)


def test_linear_log_eq_hist_and_limits():
    two = ["#000000", "#FFFFFF"]  # entry i is grey level i: a value's level is floor(t * 256)
    assert np.array_equal(colours(draw(np.array([0.0, 0.5, 1.0, 0.25]), cmap=two), 4),
                          grey([0, 128, 255, 64]))
    assert np.array_equal(colours(draw(np.array([1.0, 10.0, 100.0]), cmap=two, how="log"), 3),
                          grey([0, 128, 255]))
    # Equalised: the ranks, not the distances, of 1, 2 and 1000.
    assert np.array_equal(colours(draw([1, 2, 1000], cmap=two, how="eq_hist"), 3),
                          grey([0, 128, 255]))
    # Clipped to vmin..vmax.
    assert np.array_equal(colours(draw([-5.0, 0.5, 5.0], cmap=two, vmin=0, vmax=1), 3),
                          grey([0, 128, 255]))
    # Integers are values once cmap is given (not D3DCOLORs); alpha comes from the map.
    got = colours(draw(np.array([0, 2], np.uint32), cmap=["#FF000080", "#0000FF"]), 2)
    assert np.array_equal(got, [[255, 0, 0, 128], [0, 0, 255, 255]])


def test_matplotlib_colormaps_by_name():
    mpl = pytest.importorskip("matplotlib")
    rng = np.random.default_rng(4)
    values = rng.normal(size=W * H)
    for name in ("viridis", "magma", "coolwarm"):
        want = mpl.colormaps[name](mpl.colors.Normalize(-1, 1)(values), bytes=True)
        got = colours(draw(values, cmap=name, vmin=-1, vmax=1), W * H)
        assert np.array_equal(got, want), name
    assert np.array_equal(colours(draw(values, cmap=mpl.colormaps["plasma"]), W * H),
                          colours(draw(values, cmap="plasma"), W * H))


def test_builtin_colormaps_without_matplotlib(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # `import matplotlib` fails
    values = np.linspace(0, 1, W * H)
    fire = colours(draw(values, cmap="fire"), W * H)
    assert fire[0].tolist() == [0, 0, 0, 255] and fire[-1].tolist() == [255, 255, 255, 255]
    viridis = colours(draw(values, cmap="viridis"), W * H)
    assert viridis[0].tolist() == [0x44, 0x01, 0x54, 255]
    assert viridis[-1].tolist() == [0xFD, 0xE7, 0x24, 255]
    with pytest.raises(ValueError, match=r"^cmap: unknown colormap 'magma' \(expected one of "
                       r"the built-in viridis, fire, gray, blues, or a list of colours\)$"):
        draw(values, cmap="magma")
    monkeypatch.undo()
    mpl = pytest.importorskip("matplotlib")
    # The built-in viridis is matplotlib's at 17 stops: within 5 levels everywhere.
    want = mpl.colormaps["viridis"](values, bytes=True).astype(int)
    assert np.abs(viridis.astype(int) - want).max() <= 5


def test_categories_with_color_key():
    kinds = np.array(["oak", "elm", "oak", "ash", "elm"])
    key = {"oak": "#00FF00", "elm": (1.0, 0.0, 0.0), "ash": "#0000FF80"}
    got = colours(draw(kinds, color_key=key), 5)
    assert got.tolist() == [[0, 255, 0, 255], [255, 0, 0, 255], [0, 255, 0, 255],
                            [0, 0, 255, 128], [255, 0, 0, 255]]
    # Without a key: matplotlib's tab10 in order of first appearance.
    got = colours(draw(kinds, cmap=None, how="linear"), 5)
    assert got[:, :3].tolist()[:2] == [[0x1F, 0x77, 0xB4], [0xFF, 0x7F, 0x0E]]
    with pytest.raises(ValueError, match=r"^color_key has no colour for the category 'ash' "
                       r"of color$"):
        draw(kinds, color_key={"oak": "#00FF00", "elm": "#FF0000"})


def test_tables_colour_alike():
    pd = pytest.importorskip("pandas")
    pa = pytest.importorskip("pyarrow")
    pl = pytest.importorskip("polars")
    rng = np.random.default_rng(9)
    n = 3000
    cols = {"x": rng.uniform(-1, 1, n), "y": rng.uniform(-1, 1, n).astype(np.float32),
            "v": rng.gamma(2.0, size=n), "k": rng.choice(["a", "b", "c"], n)}
    kw = dict(width=60, height=40, x_range=(-1, 1), y_range=(-1, 1), blend="alpha")
    for spec in (dict(color="v", cmap="fire", how="log"), dict(color="v", how="eq_hist"),
                 dict(color="k", color_key={"a": "#FF000080", "b": "#00FF0080",
                                            "c": "#0000FF80"})):
        want = pointillist.points(cols["x"], cols["y"], **dict(spec, color=cols[spec["color"]]),
                                  **kw)
        assert len(np.unique(want.reshape(-1, 4), axis=0)) > 20
        table = pa.table(cols)
        for data in (pd.DataFrame(cols), table, pl.DataFrame(cols),
                     pa.Table.from_batches(table.to_batches(max_chunksize=700)),
                     pa.RecordBatchReader.from_batches(table.schema,
                                                       table.to_batches(max_chunksize=700))):
            got = pointillist.points(data, "x", "y", **spec, **kw)
            assert np.array_equal(got, want), (type(data), spec)
    bad = pa.table({"x": [0.0, 1.0], "y": [0.0, 1.0], "v": [1.0, None]})
    with pytest.raises(ValueError, match=r"^color: column 'v' is null at row 1$"):
        pointillist.points(bad, "x", "y", color="v", cmap="fire", width=4, height=4)


def test_counts_shaded():
    # Pixel 0 holds one point, pixel 1 three, pixel 2 five, the rest none.
    px = np.array([0] + [1] * 3 + [2] * 5, dtype=np.float32)
    py = np.zeros_like(px)
    kw = dict(width=W, height=H, clear=0xFF102030)
    two = ["#000000", "#FFFFFF"]
    img = pointillist.points(px, py, cmap=two, how="linear", **kw)
    assert colours(img, 3).tolist() == grey([0, 128, 255]).tolist()  # (count - 1) / 4
    assert (img.reshape(-1, 4)[3:] == [0x10, 0x20, 0x30, 0xFF]).all()  # uncovered: clear
    assert img.extent == (-0.5, W - 0.5, H - 0.5, -0.5)
    # eq_hist by default (datashader's); vmax clips.
    assert np.array_equal(pointillist.points(px, py, cmap=two, **kw),
                          pointillist.points(px, py, cmap=two, how="eq_hist", **kw))
    img = pointillist.points(px, py, cmap=two, how="linear", vmin=1, vmax=3, **kw)
    assert colours(img, 3).tolist() == grey([0, 255, 255]).tolist()
    # Arrow tables are counted batch by batch into the same counts.
    pa = pytest.importorskip("pyarrow")
    table = pa.Table.from_batches(pa.table({"x": px, "y": py}).to_batches(max_chunksize=2))
    assert np.array_equal(pointillist.points(table, "x", "y", cmap="fire", **kw),
                          pointillist.points(px, py, cmap="fire", **kw))
    for data, args in ((None, (px, py)), (table, ("x", "y"))):
        with pytest.raises(ValueError, match=r"^only a draw of one colour is shaded from its "
                           r"counts: a constant color, blend \"add\", \"max\" or \"replace\", "
                           r"no z, no texture$"):
            pointillist.points(*([data] if data is not None else []), *args, cmap="fire",
                               blend="alpha", **kw)


def test_bad_colour_arguments():
    with pytest.raises(ValueError, match=r"^how: unknown normalisation 'cbrt' \(expected one "
                       r"of: linear, log, eq_hist\)$"):
        draw([1.0, 2.0], how="cbrt")
    with pytest.raises(ValueError, match=r'^how="log" needs positive values; vmin is 0.0$'):
        draw([0.0, 2.0], how="log")
    with pytest.raises(ValueError, match=r"^color\[1\] is NaN$"):
        draw([0.0, np.nan], cmap="fire")
    with pytest.raises(ValueError, match=r"^cmap: 'nocolour' is not a colour"):
        draw([0.0, 1.0], cmap=["#000000", "nocolour"])
    with pytest.raises(ValueError, match=r"^vmin 2.0 and vmax 1.0 must be finite, "
                       r"vmin <= vmax$"):
        draw([0.0, 1.0], vmin=2, vmax=1)
