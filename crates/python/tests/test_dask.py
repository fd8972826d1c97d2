"""`pointillist.dask.points` on a two-process LocalCluster gives `pointillist.points` on all the
rows in order, bit for bit: partial images reduced for "add" and "max", screen tiles for every
order-dependent draw; with points that overlap across partitions and tiles."""

import numpy as np
import pandas as pd
import pytest

dd = pytest.importorskip("dask.dataframe")
distributed = pytest.importorskip("distributed")

import pointillist  # noqa: E402
import pointillist.dask  # noqa: E402

W, H = 120, 90


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def frame(n, seed, partitions):
    """Points crowded into the middle of the target (every pixel there is hit by points of
    several partitions and many squares straddle tile edges), fractional sizes and
    positions, colours of every alpha, depths."""
    rng = np.random.default_rng(seed)
    pdf = pd.DataFrame(
        {
            "x": rng.normal(0.5, 0.15, n),
            "y": rng.normal(0.5, 0.15, n).astype(np.float32),
            "s": rng.uniform(0.5, 7.5, n).astype(np.float32),
            "c": rng.integers(0, 2**32, n, dtype=np.uint32),
            "z": rng.uniform(0, 1, n).astype(np.float32),
        }
    )
    return pdf, dd.from_pandas(pdf, npartitions=partitions, sort=False)


def both(pdf, df, client, **kw):
    """(dask result, pointillist.points on all rows)."""
    cols = {k: kw.pop(k) for k in ("size", "color", "z") if isinstance(kw.get(k), str)}
    tiling = {k: kw.pop(k) for k in ("tile_size",) if k in kw}
    got = pointillist.dask.points(df, "x", "y", client=client, **cols, **tiling, **kw)
    args = {k: pdf[c].to_numpy() for k, c in cols.items()}
    want = pointillist.points(pdf["x"].to_numpy(), pdf["y"].to_numpy(), **args, **kw)
    return got, want


def test_the_cluster_has_two_worker_processes(client):
    workers = client.scheduler_info()["workers"]
    assert len(workers) == 2
    pids = client.run(lambda: __import__("os").getpid())
    assert len(set(pids.values())) == 2


@pytest.mark.parametrize("blend", ["add", "max"])
def test_reduced_partial_images_equal_one_sequential_draw(client, blend):
    pdf, df = frame(60_000, 1, 7)
    got, want = both(
        pdf, df, client, size="s", color="c", blend=blend, width=W, height=H,
        x_range=(0, 1), y_range=(0, 1), clear=0xFF304050,
    )
    assert isinstance(got, pointillist.Image)
    assert np.array_equal(got, want)
    if blend == "add":
        # Saturation happened (the reduction's clamp is exercised) and the middle got
        # contributions from every partition.
        assert (want[..., :3] == 255).mean() > 0.2
    # The clear colour is combined once: a second combination would show where no point is.
    assert want[0, 0].tolist() == [0x30, 0x40, 0x50, 0xFF]


@pytest.mark.parametrize(
    "blend,depth,tile", [("alpha", False, 16), ("replace", False, 25), ("add", True, 31),
                         ("alpha", True, 64)]
)
def test_tiles_equal_one_sequential_draw(client, blend, depth, tile):
    pdf, df = frame(30_000, 2, 5)
    got, want = both(
        pdf, df, client, size="s", color="c", z="z" if depth else None, blend=blend,
        width=W, height=H, x_range=(0, 1), y_range=(0, 1), tile_size=tile,
    )
    assert np.array_equal(got, want)
    assert len(np.unique(want.reshape(-1, 4), axis=0)) > 500


def test_constant_size_colour_and_texture(client):
    pdf, df = frame(20_000, 3, 4)
    tex = np.random.default_rng(7).integers(0, 256, (6, 5, 4), dtype=np.uint8)
    for blend in ("add", "alpha"):
        got, want = both(
            pdf, df, client, size=5.5, color=0x80FF8040, blend=blend, width=W, height=H,
            x_range=(0, 1), y_range=(0, 1), texture=tex, tile_size=(40, 17),
        )
        assert np.array_equal(got, want), blend


@pytest.mark.parametrize(
    "kind,persist",
    [("counted", True), ("counted", False), ("partial", True), ("partial", False),
     ("tiles", False), ("depth tiles", False)],
)
def test_behaviours_reach_every_partition_and_tile(client, kind, persist):
    # Sizes below one pixel: most squares cover no pixel centre and draw nothing by default;
    # minimum_size=one_pixel draws every one as size 1. The counts, the partial images and
    # the tiles (including which tiles a point is sent to) all draw with the switch.
    pdf, df = frame(3_000, 8, 5)
    pdf["s"] = np.random.default_rng(9).uniform(0.0, 0.9, len(pdf)).astype(np.float32)
    df = dd.from_pandas(pdf, npartitions=5, sort=False)
    if persist:
        df = df.persist()
    kw = dict(
        width=W, height=H, x_range=(0, 1), y_range=(0, 1), clear=0xFF102030, size="s",
        color=0x20406080 if kind == "counted" else "c",
        blend={"counted": "add", "partial": "max"}.get(kind, "alpha"),
        z="z" if kind == "depth tiles" else None, tile_size=(23, 17),
    )
    got, want = both(pdf, df, client, behaviour={"minimum_size": "one_pixel"}, **dict(kw))
    assert np.array_equal(got, want)
    got_default, default = both(pdf, df, client, **dict(kw))
    assert np.array_equal(got_default, default)
    # The switch changed many pixels: more of them are drawn.
    drawn = lambda img: int((img != [0x10, 0x20, 0x30, 0xFF]).any(axis=2).sum())  # noqa: E731
    assert drawn(want) > drawn(default) + 500, (drawn(want), drawn(default))


def test_errors_name_the_argument(client):
    pdf, df = frame(100, 4, 2)
    with pytest.raises(ValueError, match=r"column 'w' is not in the DataFrame"):
        pointillist.dask.points(df, "w", "y", width=8, height=8, client=client)
    with pytest.raises(ValueError, match="unknown blend"):
        pointillist.dask.points(df, width=8, height=8, blend="over", client=client)
    with pytest.raises(ValueError, match="x_range"):
        pointillist.dask.points(df, width=8, height=8, x_range=(1, 0), client=client)
    with pytest.raises(ValueError) as info:
        pointillist.dask.points(df, width=8, height=8, behaviour={"size": "1"}, client=client)
    assert str(info.value).startswith("behaviour: unknown behaviour `size` (expected one of: ")
    with pytest.raises(TypeError, match=r"^behaviour must be a dict"):
        pointillist.dask.points(df, width=8, height=8, behaviour=[1], client=client)
    # Sizes no target has: the device's one line, before any image is allocated (2**30 x 16
    # aborted the interpreter; -1 was an OverflowError naming nothing).
    for w, h in [(2**30, 16), (-1, 8)]:
        with pytest.raises(pointillist.Error, match=rf"^render target {w}x{h} is outside"):
            pointillist.dask.points(df, width=w, height=h, client=client)
    bad = pdf.copy()
    bad.loc[60, "x"] = np.nan
    bdf = dd.from_pandas(bad, npartitions=2, sort=False)
    with pytest.raises(ValueError, match=r"partition 1: x\[10\] is NaN"):
        pointillist.dask.points(bdf, width=8, height=8, client=client)
    with pytest.raises(ValueError, match=r"partition 1: x\[10\] is NaN"):
        pointillist.dask.points(bdf, width=8, height=8, blend="alpha", client=client)


@pytest.mark.parametrize("blend", ["add", "max", "replace"])
@pytest.mark.parametrize("size", [2.5, "s"])
def test_counted_draws_of_one_colour_equal_one_sequential_draw(client, blend, size):
    # One colour, no depth, no texture: partitions send per-pixel counts, added and mapped on
    # the client. 60 000 points crowded on 40x30 cover the middle more than 255 times.
    pdf, df = frame(60_000, 5, 7)
    # A small colour for "add", so counts up to about 70 give colours of their own.
    colour = 0x01030507 if blend == "add" else 0x80C04010
    got, want = both(
        pdf, df.persist(), client, size=size, color=colour, blend=blend, width=40,
        height=30, x_range=(0, 1), y_range=(0, 1), clear=0xFF304050,
    )
    assert isinstance(got, pointillist.Image)
    assert np.array_equal(got, want)
    assert len(np.unique(want.reshape(-1, 4), axis=0)) > (30 if blend == "add" else 1)
    plot = pointillist.Plot(40, 30, x_range=(0, 1), y_range=(0, 1), clear=0)
    counts = pointillist._native._counts(
        plot, (pdf["x"].to_numpy(), pdf["y"].to_numpy(), None, 2.5, 1)
    )
    assert counts.dtype == np.uint8 and counts.shape == (30, 40)
    assert (counts == 255).sum() > 50 and (counts == 0).sum() > 50


def test_counts_into_one_array():
    # _counts(out=...) adds each part's counts to out, saturating: equal to the counts of all.
    pdf, _ = frame(60_000, 5, 1)
    x, y, s = (pdf[c].to_numpy() for c in ("x", "y", "s"))
    plot = pointillist.Plot(40, 30, x_range=(0, 1), y_range=(0, 1), clear=0)
    counts = pointillist._native._counts
    whole = counts(plot, (x, y, None, s, 1))
    out = np.full((30, 40), 3, np.uint8)
    for rows in (slice(0, 7), slice(7, 40_000), slice(40_000, None)):
        got = counts(plot, (x[rows], y[rows], None, s[rows], 1), out=out)
        assert got is out
    assert np.array_equal(out, np.minimum(whole.astype(int) + 3, 255))
    assert (whole == 255).sum() > 50 and ((whole > 0) & (whole < 252)).sum() > 50
    c = pdf["c"].to_numpy()
    before = out.copy()
    assert counts(plot, (x, y, None, s, c), out=out) is None
    assert np.array_equal(out, before)
    with pytest.raises(ValueError, match=r"out has shape \(40, 30\), not \(30, 40\)"):
        counts(plot, (x, y, None, s, 1), out=np.zeros((40, 30), np.uint8))
    with pytest.raises(ValueError, match="out must be C-contiguous"):
        counts(plot, (x, y, None, s, 1), out=np.zeros((40, 30), np.uint8).T)


def test_tasks_draw_on_their_workers_threads(client):
    # One thread a worker: the tasks count and draw on a pool of one thread, with the same
    # result as rayon's global pool.
    assert client.submit(pointillist.dask._threads, pure=False).result() == 1
    assert pointillist.dask._threads() is None
    pdf, _ = frame(400_000, 12, 1)
    x, y, c = (pdf[k].to_numpy() for k in ("x", "y", "c"))
    plot = pointillist.Plot(W, H, x_range=(0, 1), y_range=(0, 1), clear=0)
    one, many = (x, y, None, 1.5, 1), (x, y, None, 1.5, c)
    counts = pointillist._native._counts(plot, one)
    image = pointillist._native._partial(plot, many)
    for threads in (1, 2, 3):
        got = pointillist._native._counts(plot, one, threads=threads)
        assert np.array_equal(got, counts), threads
        got = pointillist._native._partial(plot, many, threads=threads)
        assert np.array_equal(got, image), threads
    with pytest.raises(ValueError, match="threads must be at least 1"):
        pointillist._native._counts(plot, one, threads=0)


def holders(client, df):
    """The worker holding each partition of persisted ``df``, in order."""
    futures = [f for _, f in sorted((f.key[1], f) for f in distributed.futures_of(df))]
    who = client.who_has(futures)
    return [who[f.key][0] for f in futures]


def test_partitions_are_grouped_by_the_worker_holding_them(client):
    _, df = frame(1000, 6, 9)
    df = df.persist()
    distributed.wait(df)
    held = pointillist.dask._held(df, client)
    assert sorted(held) == sorted(client.scheduler_info()["workers"])
    assert sorted(p for parts in held.values() for p, _ in parts) == list(range(9))
    where = holders(client, df)
    for worker, parts in held.items():
        assert [p for p, _ in parts] == sorted(p for p, _ in parts)
        assert all(where[p] == worker for p, _ in parts)
    # Not persisted, or derived from a persisted frame (other keys): no futures to use.
    assert pointillist.dask._held(frame(100, 6, 3)[1], client) is None
    assert pointillist.dask._held(df[df.x > 0.5], client) is None
    assert pointillist.dask._held(df, None) is None


def spread(client, pdf, counts):
    """``pdf`` in a persisted Dask DataFrame whose partitions lie on the cluster's workers,
    ``counts[i]`` of them (in a row) on worker ``i``."""
    workers = sorted(client.scheduler_info()["workers"])
    n = sum(counts)
    bounds = np.linspace(0, len(pdf), n + 1).astype(int)
    on = [w for w, c in zip(workers, counts) for _ in range(c)]
    futures = [
        client.scatter(pdf.iloc[bounds[i] : bounds[i + 1]], workers=[w])
        for i, w in enumerate(on)
    ]
    df = dd.from_delayed(futures, meta=pdf.iloc[:0], verify_meta=False).persist()
    distributed.wait(df)
    return df, on


@pytest.mark.parametrize("counts", [(5, 1), (0, 4), (3, 3)])
@pytest.mark.parametrize("kind", ["counted", "partial"])
def test_persisted_partitions_drawn_where_they_lie(client, counts, kind):
    # One task a worker holding partitions (none on a worker holding none), on that worker;
    # the result equals the graph's (not persisted) and one sequential draw.
    pdf, lazy = frame(40_000, 8, sum(counts))
    df, on = spread(client, pdf, counts)
    assert holders(client, df) == on
    kw = dict(width=W, height=H, x_range=(0, 1), y_range=(0, 1), clear=0xFF304050, size="s")
    kw.update(color=0x01030507) if kind == "counted" else kw.update(color="c")
    with distributed.get_task_stream(client=client) as ts:
        got, want = both(pdf, df, client, **kw)
    assert np.array_equal(got, want)
    assert np.array_equal(both(pdf, lazy, client, **kw)[0], want)
    name = "_count_held-" if kind == "counted" else "_partial_held-"
    ran = [t for t in ts.data if str(t["key"]).startswith(name)]
    assert sorted(t["worker"] for t in ran) == sorted(set(on))
    assert not [t for t in ts.data if str(t["key"]).startswith(("_count-", "_partial-"))]


def test_persisted_nan_names_its_partition(client):
    pdf, _ = frame(300, 9, 3)
    pdf.loc[110, "x"] = np.nan
    df, _ = spread(client, pdf, (1, 2))
    for color in (0xFFFFFFFF, "c"):
        with pytest.raises(ValueError, match=r"partition 1: x\[10\] is NaN"):
            pointillist.dask.points(df, color=color, width=8, height=8, client=client)


@pytest.mark.parametrize("kind", ["counted", "partial"])
def test_many_workers_results_reduced_on_the_workers_first(client, kind):
    # Five (worker, partitions) items with split_every 2: combining tasks on the workers until
    # two arrays are left, added on the client.
    pdf, _ = frame(20_000, 10, 5)
    df, on = spread(client, pdf, (2, 3))
    held = pointillist.dask._held(df, client)
    items = [(w, [pf]) for w, parts in held.items() for pf in parts]
    plot = pointillist.Plot(W, H, x_range=(0, 1), y_range=(0, 1))
    columns, constants = {"x": "x", "y": "y", "size": "s"}, {"size": None, "color": 0x01030507}
    if kind == "counted":
        fn, args = pointillist.dask._count_held, (columns, constants, plot)
        combine, add = pointillist.dask._add_counts, pointillist._native._add_counts
    else:
        columns["color"], constants["color"] = "c", None
        fn, args = pointillist.dask._partial_held, (columns, constants, plot)
        combine = lambda a: pointillist.dask._combine(a, plot)  # noqa: E731
        add = lambda d, s: pointillist._native._combine(d, s, plot)  # noqa: E731
    with distributed.get_task_stream(client=client) as ts:
        got = pointillist.dask._gather_sum(client, fn, items, args, combine, add, 2)
    assert len([t for t in ts.data if "held" in str(t["key"])]) == 5
    # 5 arrays to 3, 3 to 2.
    combined = [t for t in ts.data if str(t["key"]).startswith(("lambda", "_add_counts"))]
    assert len(combined) == 5
    want = pointillist.dask._gather_sum(client, fn, held.items(), args, combine, add, 8)
    assert np.array_equal(got, want)
    if kind == "counted":
        direct = pointillist._native._counts(
            plot, (pdf["x"].to_numpy(), pdf["y"].to_numpy(), None, pdf["s"].to_numpy(), 0x01030507)
        )
        assert np.array_equal(got, direct)


def test_repeated_calls_recompute(client):
    # Every call has fresh keys: a second call is not answered by the first one's result.
    pdf, df = frame(5000, 7, 3)
    kw = dict(width=16, height=16, x_range=(0, 1), y_range=(0, 1))
    with distributed.get_task_stream(client=client) as ts:
        a = pointillist.dask.points(df, client=client, **kw)
        b = pointillist.dask.points(df, client=client, **kw)
    assert np.array_equal(a, b)
    counted = [t for t in ts.data if str(t["key"]).startswith("_count-")]
    assert len(counted) == 6


@pytest.mark.parametrize("persist", [False, True])
def test_counts_shaded_with_a_colormap(client, persist):
    # The partitions' counts, added, shaded as pointillist.points shades the counts of all
    # the rows at once (item 3: datashader's tf.shade on pointillist's counts).
    pdf, df = frame(40_000, 6, 5)
    df = df.persist() if persist else df
    kw = dict(width=40, height=30, x_range=(0, 1), y_range=(0, 1), clear=0xFF304050)
    for shade in (dict(cmap="fire"), dict(cmap=["#000000", "#FFFFFF"], how="linear", vmax=50),
                  dict(cmap="viridis", how="log", size="s")):
        got, want = both(pdf, df, client, **shade, **kw)
        assert np.array_equal(got, want), shade
        assert len(np.unique(want.reshape(-1, 4), axis=0)) > 20
        assert (got.x_name, got.extent) == ("x", (0.0, 1.0, 0.0, 1.0))
    with pytest.raises(ValueError, match="only a draw of one colour is shaded"):
        pointillist.dask.points(df, "x", "y", blend="alpha", cmap="fire", client=client, **kw)


@pytest.mark.parametrize("persist", [False, True])
def test_colour_from_values_equals_one_draw(client, persist):
    # Every partition colours its points with the column's global vmin and vmax (or those
    # given): the result is pointillist.points' on all the rows, for any blend and strategy.
    pdf, df = frame(20_000, 7, 5)
    pdf["v"] = np.random.default_rng(7).gamma(2.0, size=len(pdf))
    pdf["k"] = pd.Categorical(np.random.default_rng(8).choice(["a", "b", "c"], len(pdf)))
    df = dd.from_pandas(pdf, npartitions=5, sort=False)
    df = df.persist() if persist else df
    kw = dict(width=W, height=H, x_range=(0, 1), y_range=(0, 1), clear=0xFF304050)
    key = {"a": "#FF000080", "b": "#00FF0080", "c": "#0000FF80"}
    for shade, least in ((dict(color="v", cmap="viridis", blend="alpha"), 20),
                         (dict(color="v", cmap="fire", how="log", vmin=0.5, vmax=8), 20),
                         (dict(color="k", color_key=key, blend="replace", size="s", z="z"), 4)):
        got, want = both(pdf, df, client, **shade, **kw)
        assert np.array_equal(got, want), shade
        assert len(np.unique(want.reshape(-1, 4), axis=0)) >= least
    with pytest.raises(TypeError, match=r'^how="eq_hist" of a column\'s values is not drawn'):
        pointillist.dask.points(df, "x", "y", color="v", how="eq_hist", client=client, **kw)
    with pytest.raises(TypeError, match=r"^color: column 'k' holds categories; on Dask give "
                       r"color_key"):
        pointillist.dask.points(df, "x", "y", color="k", cmap="fire", client=client, **kw)


@pytest.mark.parametrize("blend", ["alpha", "add"])
def test_circles_in_data_units_are_exact_on_the_cluster(client, blend):
    """Circles (a textured sprite) sized in data units: tiles for "alpha", partial images for
    "add", both bit for bit the single-process draw."""
    pdf, df = frame(3000, 17, 4)
    pdf["s"] = (pdf["s"] / 200).astype(np.float32)
    df = dd.from_pandas(pdf, npartitions=4, sort=False)
    got, want = both(
        pdf, df, client, size="s", color="c", width=W, height=H, blend=blend,
        x_range=(0, 1), y_range=(0, 1), marker="circle", size_units="data", tile_size=32,
    )
    assert np.array_equal(got, want)
    assert (np.asarray(want)[..., 3] > 0).sum() > 1000
