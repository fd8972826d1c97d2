"""`points(data, x="col", y="col", ...)`: a pandas DataFrame or a dict of arrays drawn by
column names, bit for bit as the same columns passed as arrays (which test_points compares
with the CLI); numpy-backed columns read in place; nulls refused naming column and row."""

import tracemalloc

import numpy as np
import pandas as pd
import pytest

import pointillist
import pointillist.dask

KW = dict(width=53, height=41, x_range=(-1, 1), y_range=(-1, 1), clear=0xFF102030)


def frame(n=400, seed=8):
    rng = np.random.default_rng(seed)
    return pd.DataFrame({
        "lon": rng.uniform(-1.1, 1.1, n),
        "lat": rng.uniform(-1.1, 1.1, n).astype(np.float32),
        "s": rng.uniform(0.5, 6.0, n).astype(np.float32),
        # Every alpha, small red, green and blue: "add" saturates few pixels.
        "c": rng.integers(0, 2**32, n, dtype=np.uint32) & np.uint32(0xFF1F1F1F),
        "d": rng.uniform(0, 1, n).astype(np.float32),
    })


@pytest.mark.parametrize("blend", ["add", "alpha", "max", "replace"])
@pytest.mark.parametrize("depth", [False, True])
def test_frame_by_names_equals_the_arrays(blend, depth):
    df = frame()
    z = "d" if depth else None
    got = pointillist.points(df, x="lon", y="lat", size="s", color="c", z=z, blend=blend, **KW)
    want = pointillist.points(
        df["lon"].to_numpy(), df["lat"].to_numpy(), size=df["s"].to_numpy(),
        color=df["c"].to_numpy(), z=df["d"].to_numpy() if depth else None, blend=blend, **KW,
    )
    assert np.array_equal(got, want)
    assert len(np.unique(want.reshape(-1, 4), axis=0)) > 10
    assert (got.x_name, got.y_name, got.extent) == ("lon", "lat", (-1.0, 1.0, -1.0, 1.0))
    # A dict of the same arrays, positional names, and constants beside column names.
    as_dict = {k: df[k].to_numpy() for k in df.columns}
    assert np.array_equal(
        pointillist.points(as_dict, "lon", "lat", size="s", color="c", z=z, blend=blend, **KW),
        want,
    )
    one = pointillist.points(df, "lon", "lat", size=2.5, color=0x80C04010, blend=blend, **KW)
    assert np.array_equal(one, pointillist.points(
        df["lon"].to_numpy(), df["lat"].to_numpy(), size=2.5, color=0x80C04010, blend=blend,
        **KW))


def test_numpy_columns_are_read_in_place():
    n = 2_000_000
    rng = np.random.default_rng(1)
    df = pd.DataFrame({"x": rng.uniform(0, 1, n).astype(np.float32),
                       "y": rng.uniform(0, 1, n).astype(np.float32)})
    kw = dict(width=64, height=64, x_range=(0, 1), y_range=(0, 1))
    pointillist.points(df, "x", "y", **kw)  # warm up
    tracemalloc.start()
    img = pointillist.points(df, "x", "y", **kw)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    # The columns are 8 MB each; the image is 16 KB (numpy's allocations are traced).
    assert peak < 200_000, peak
    assert img[..., 0].sum() > 0


def test_nullable_columns():
    df = frame(500)
    want = pointillist.points(df, "lon", "lat", size="s", color="c", **KW)
    nullable = df.astype({"lon": "Float64", "s": "Float32", "c": "UInt32"})
    assert np.array_equal(pointillist.points(nullable, "lon", "lat", size="s", color="c", **KW),
                          want)
    for column, arg in (("lon", "x"), ("s", "size"), ("c", "color")):
        bad = nullable.copy()
        bad.loc[137, column] = pd.NA
        with pytest.raises(ValueError) as info:
            pointillist.points(bad, "lon", "lat", size="s", color="c", **KW)
        assert str(info.value) == f"{arg}: column {column!r} is null at row 137"


def test_bad_tables_name_the_argument():
    df = frame(10)

    def error(exc, message, *args, **kw):
        with pytest.raises(exc) as info:
            pointillist.points(*args, width=8, height=8, **kw)
        assert str(info.value) == message

    error(ValueError, "y: column 'height' is not in data (its columns: lon, lat, s, c, d)",
          df, "lon", "height")
    error(ValueError, "color: column 'rgb' is not in data (its columns: lon, lat, s, c, d)",
          df, "lon", "lat", color="rgb")
    error(TypeError, "x='lon' names a column, but no data was given", x="lon", y="lat")
    error(TypeError, "y must be a column name with data; got ndarray", df, "lon", np.zeros(10))
    error(TypeError, "points takes the arrays x and y, or data and the names of its x and y "
          "columns", np.zeros(3))
    error(TypeError, "data must be a pandas DataFrame, a dict of arrays or an Arrow table (an "
          "object with __arrow_c_stream__ or __arrow_c_array__); got list", [[1.0], [1.0]],
          "lon", "lat")
    # A NaN position in a numpy column: the array's own error.
    bad = df.copy()
    bad.loc[4, "lat"] = np.nan
    error(ValueError, "y[4] is NaN", bad, "lon", "lat")


def test_dask_reads_nullable_columns_alike():
    import dask.dataframe as dd

    pdf = frame(400).astype({"lon": "Float64"})
    df = dd.from_pandas(pdf, npartitions=2, sort=False)
    got = pointillist.dask.points(df, "lon", "lat", size="s", color="c", blend="alpha", **KW)
    want = pointillist.points(pdf, "lon", "lat", size="s", color="c", blend="alpha", **KW)
    assert np.array_equal(got, want)
    pdf.loc[250, "lon"] = pd.NA
    df = dd.from_pandas(pdf, npartitions=2, sort=False)
    with pytest.raises(ValueError, match=r"^partition 1: x: column 'lon' is null at row 50$"):
        pointillist.dask.points(df, "lon", "lat", **KW)
