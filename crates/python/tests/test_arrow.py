"""`points(data, x="col", ...)` with Arrow tables (the PyCapsule interface: pyarrow, polars):
bit for bit as the same columns passed as numpy arrays (which test_points compares with the
CLI), record batch after record batch in the order of the rows, float32/float64 read in
place, nulls refused naming the argument, the column and the row."""

import subprocess
import sys

import numpy as np
import pytest

import pointillist

pa = pytest.importorskip("pyarrow")

KW = dict(width=53, height=41, x_range=(-1, 1), y_range=(-1, 1), clear=0xFF102030)
NAMES = dict(x="lon", y="lat", size="s", color="c")


def columns(n=600, seed=8):
    rng = np.random.default_rng(seed)
    return {
        "lon": rng.uniform(-1.1, 1.1, n),
        "lat": rng.uniform(-1.1, 1.1, n).astype(np.float32),
        "s": rng.uniform(0.5, 6.0, n).astype(np.float32),
        # Every alpha, small red, green and blue: "add" saturates few pixels.
        "c": rng.integers(0, 2**32, n, dtype=np.uint32) & np.uint32(0xFF1F1F1F),
        "d": rng.uniform(0, 1, n).astype(np.float32),
    }


def from_arrays(cols, z=None, **kw):
    """The reference: the same columns as numpy arrays."""
    return pointillist.points(cols["lon"], cols["lat"], size=cols["s"], color=cols["c"],
                              z=None if z is None else cols[z], **{**KW, **kw})


def chunked(cols, cuts):
    """A pyarrow Table of `cols` in record batches cut at rows `cuts` (an empty one too)."""
    table = pa.table(cols)
    edges = [0, *cuts, table.num_rows]
    batches = [table.slice(a, b - a).to_batches()[0] if b > a else
               pa.RecordBatch.from_pylist([], schema=table.schema)
               for a, b in zip(edges, edges[1:])]
    return pa.Table.from_batches(batches, schema=table.schema)


@pytest.mark.parametrize("blend", ["add", "alpha", "max", "replace"])
@pytest.mark.parametrize("depth", [False, True])
def test_pyarrow_table_equals_the_arrays(blend, depth):
    cols = columns()
    z = "d" if depth else None
    want = from_arrays(cols, z=z, blend=blend)
    assert len(np.unique(want.reshape(-1, 4), axis=0)) > 10
    table = pa.table(cols)
    got = pointillist.points(table, **NAMES, z=z, blend=blend, **KW)
    assert np.array_equal(got, want)
    assert (got.x_name, got.y_name, got.extent) == ("lon", "lat", (-1.0, 1.0, -1.0, 1.0))
    # Record batches in order, an empty one among them, equal the one batch.
    many = chunked(cols, [1, 100, 100, 333, 599])
    assert many.column("lon").num_chunks == 6
    assert np.array_equal(pointillist.points(many, **NAMES, z=z, blend=blend, **KW), want)
    # A RecordBatchReader (a stream read once), and a RecordBatch.
    reader = pa.RecordBatchReader.from_batches(many.schema, many.to_batches())
    assert np.array_equal(pointillist.points(reader, **NAMES, z=z, blend=blend, **KW), want)
    batch = table.to_batches()[0]
    assert np.array_equal(pointillist.points(batch, **NAMES, z=z, blend=blend, **KW), want)


@pytest.mark.parametrize("blend", ["add", "max", "replace", "alpha"])
def test_one_colour_chunked_equals_the_arrays(blend):
    # One colour, no depth: "add", "max" and "replace" are counted, chunk by chunk, into one
    # count image; the saturated pixels (255 and more points) show it adds across chunks.
    rng = np.random.default_rng(3)
    n = 30_000
    x = rng.normal(0, 0.2, n)
    y = rng.normal(0, 0.2, n).astype(np.float32)
    kw = dict(KW, color=0x0A030201, blend=blend)
    want = pointillist.points(x, y, **kw)
    table = chunked({"x": x, "y": y}, [7, 9000, 20000])
    assert np.array_equal(pointillist.points(table, "x", "y", **kw), want)
    sizes = rng.uniform(0.5, 3, n).astype(np.float32)
    want = pointillist.points(x, y, size=sizes, **kw)
    table = chunked({"x": x, "y": y, "s": sizes}, [12_345])
    assert np.array_equal(pointillist.points(table, "x", "y", size="s", **kw), want)
    if blend == "add":
        assert (want[..., 0] == 255).any() and (want[..., 0] < 255).any()


def test_polars_frame_equals_the_arrays():
    pl = pytest.importorskip("polars")
    cols = columns(800)
    want = from_arrays(cols, blend="alpha")
    df = pl.DataFrame(cols)
    assert np.array_equal(pointillist.points(df, **NAMES, blend="alpha", **KW), want)
    # A frame of several chunks, and polars' own dtypes: Int64 colours, Int32 positions.
    parts = [pl.DataFrame({k: v[a:b] for k, v in cols.items()})
             for a, b in ((0, 250), (250, 251), (251, 800))]
    many = pl.concat(parts, rechunk=False)
    assert many.n_chunks() == 3
    assert np.array_equal(pointillist.points(many, **NAMES, blend="alpha", **KW), want)
    wide = df.with_columns(pl.col("c").cast(pl.Int64))
    assert np.array_equal(pointillist.points(wide, **NAMES, blend="alpha", **KW), want)
    ints = pl.DataFrame({"i": np.arange(-20, 30, dtype=np.int32),
                         "j": np.arange(50, dtype=np.int64) % 7})
    assert np.array_equal(
        pointillist.points(ints, "i", "j", size=2.0, blend="add", width=40, height=9),
        pointillist.points(np.arange(-20, 30, dtype=np.float64),
                           np.arange(50, dtype=np.float64) % 7, size=2.0, width=40, height=9))



def test_duckdb_result_equals_the_arrays():
    """A DuckDB relation speaks __arrow_c_stream__: drawn by column names (its rows in the
    query's order), and coloured from a column's values, it is the arrays' draw."""
    duckdb = pytest.importorskip("duckdb")
    cols = columns(700)
    con = duckdb.connect()
    con.register("pts", pa.table({**cols, "i": np.arange(700)}))
    rel = con.sql("select lon, lat, s, c, lon * lat as v from pts")
    assert np.array_equal(pointillist.points(rel, **NAMES, blend="alpha", **KW),
                          from_arrays(cols, blend="alpha"))
    shaded = dict(width=53, height=41, x_range=(-1, 1), y_range=(-1, 1), cmap="viridis",
                  blend="alpha")
    by_name = pointillist.points(con.sql("select lon, lat, lon * lat as v from pts"),
                                 x="lon", y="lat", color="v", **shaded)
    by_array = pointillist.points(cols["lon"], cols["lat"],
                                  color=cols["lon"] * cols["lat"].astype(np.float64), **shaded)
    assert np.array_equal(by_name, by_array)
    with pytest.raises(ValueError, match="lat.* null at row 3"):
        pointillist.points(
            con.sql("select lon, case when i = 3 then null else lat end as lat from pts"),
            x="lon", y="lat", width=8, height=8)

def test_nulls_name_the_argument_column_and_row():
    cols = columns(500)
    for column, arg in (("lon", "x"), ("lat", "y"), ("s", "size"), ("c", "color"),
                        ("d", "z")):
        values = [None if i == 337 else v for i, v in enumerate(cols[column].tolist())]
        bad = dict(cols, **{column: pa.array(values, type=pa.from_numpy_dtype(
            cols[column].dtype))})
        table = pa.table(bad)
        # In the one batch, and in the third of four (the row counted over the table).
        for data in (table, pa.Table.from_batches(table.to_batches(max_chunksize=150))):
            with pytest.raises(ValueError) as info:
                pointillist.points(data, **NAMES, z="d", **KW)
            assert str(info.value) == f"{arg}: column {column!r} is null at row 337"
    pl = pytest.importorskip("polars")
    df = pl.DataFrame({"lon": [0.0, 0.5, None], "lat": [0.0, 0.1, 0.2]})
    with pytest.raises(ValueError, match=r"^x: column 'lon' is null at row 2$"):
        pointillist.points(df, "lon", "lat", **KW)
    # A NaN is no null: the position's own error, its row counted over the table.
    lat = cols["lat"].copy()
    lat[420] = np.nan
    table = pa.Table.from_batches(pa.table(dict(cols, lat=lat)).to_batches(max_chunksize=100))
    with pytest.raises(ValueError, match=r"^y\[420\] is NaN$"):
        pointillist.points(table, **NAMES, blend="alpha", **KW)


def test_bad_arrow_tables_name_the_argument():
    table = pa.table({"lon": [0.5, 0.1], "lat": [0.2, 0.3], "name": ["a", "b"],
                      "f": [0.5, 2.0], "big": pa.array([1, 2**32], type=pa.int64())})

    def error(exc, message, *args, **kw):
        with pytest.raises(exc) as info:
            pointillist.points(*args, width=8, height=8, **kw)
        assert str(info.value) == message

    error(ValueError, "y: column 'height' is not in data (its columns: lon, lat, name, f, "
          "big)", table, "lon", "height")
    error(TypeError, "x: column 'name' has Arrow type Utf8; expected numbers (float32 and "
          "float64 are read in place)", table, "name", "lat")
    error(TypeError, "color: column 'f' has Arrow type Float64; expected uint32 D3DCOLORs "
          "0xAARRGGBB (other integers are converted)", table, "lon", "lat", color="f")
    error(ValueError, "color: column 'big' holds values outside 0..=0xFFFFFFFF (D3DCOLORs "
          "0xAARRGGBB)", table, "lon", "lat", color="big")
    error(TypeError, "with an Arrow table as data, size must be a column name or a constant, "
          "not an array (add the array to the table as a column)", table, "lon", "lat",
          size=np.ones(2))
    error(TypeError, "y must be a column name with data; got ndarray", table, "lon",
          np.zeros(2))
    error(TypeError, "data is an Arrow array of type Float64, not a table (a struct array: a "
          "record batch)", pa.array([1.0]), "lon", "lat")


def test_an_empty_table_draws_the_clear_colour():
    table = pa.table({"x": pa.array([], pa.float32()), "y": pa.array([], pa.float64()),
                      "c": pa.array([], pa.uint32())})
    for color in (0xFFFFFFFF, "c"):
        img = pointillist.points(table, "x", "y", color=color, width=5, height=4,
                                 clear=0x80102030)
        assert (img.reshape(-1, 4) == [0x10, 0x20, 0x30, 0x80]).all()


def test_float_columns_are_read_in_place():
    # A draw of 8 million float32 rows (32 MB a column) grows the process's peak memory by
    # far less than one column: the producer's buffers are read where they lie. Run in a
    # process of its own, whose peak is its own.
    script = """
import resource, numpy as np, pyarrow as pa, pointillist
n = 8_000_000
rng = np.random.default_rng(1)
table = pa.table({"x": rng.uniform(0, 1, n).astype(np.float32),
                  "y": rng.uniform(0, 1, n).astype(np.float32)})
kw = dict(width=64, height=64, x_range=(0, 1), y_range=(0, 1))
pointillist.points(np.zeros(1, np.float32), np.zeros(1, np.float32), **kw)
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
for blend in ("add", "alpha"):
    img = pointillist.points(table, "x", "y", blend=blend, **kw)
    assert img[..., 0].sum() > 0
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before)
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         check=True)
    grown_kib = int(out.stdout.strip())
    assert grown_kib < 16 * 1024, grown_kib
