"""Side-by-side benchmarks of the Python package (docs/PERFORMANCE.md, "Python"); not run in CI.

Every comparison alternates its two sides round by round on the same data in one run and
reports the median wall time of each side, the median of the per-round ratios, and the CPU
seconds of the process per round (a side that uses one core shows CPU = wall):

- bindings: ``pointillist.points`` against the Rust API (``Plot::render`` in
  crates/plot/examples/time_render.rs, a second process given the same float32 data), 1 M and
  10 M uniformly scattered one-pixel additive points on 1000x1000;
- datashader: ``Canvas.points`` + ``tf.shade`` on a pandas DataFrame of the same float32
  columns against ``pointillist.points``, 10 M and 100 M points, 1000x1000;
- matplotlib: ``Axes.scatter`` of one-pixel markers on a 1000x1000 Agg canvas, drawn, against
  ``pointillist.points``, 1 M points;
- dask: ``pointillist.dask.points`` on a two-worker ``LocalCluster`` (one thread each) against
  ``pointillist.points`` in this process, 100 M points in 20 partitions already in the
  workers' memory, ten on each (DASK_PLACEMENT=scheduler: where the scheduler puts them; the
  split is printed); the two images are
  checked to be equal (every call computes: its keys are fresh, so no result of an earlier
  call is reused). The dask side's CPU is this process's plus the workers'. DASK_ROUNDS
  (default 5) sets the rounds;
- frames: ``pointillist.points(df, x="x", y="y", ...)`` on a pandas DataFrame (its numpy
  columns), a polars DataFrame and a pyarrow Table (both read through the Arrow PyCapsule
  interface, ``__arrow_c_stream__``), each against ``pointillist.points(x, y, ...)`` on the
  numpy arrays the frame was made of (the cost of the frame path, as a ratio), and the pandas
  frame against datashader's ``Canvas.points(df, "x", "y")`` + ``tf.shade``; the same
  one-pixel additive draw as above, 10 M points, 1000x1000. Each frame's image is asserted
  equal, byte for byte, to the arrays' image;
- cmap: colour from a value column ``v = (x + y) / 2`` with the "viridis" colormap, three
  draws that are alike but not the same computation:

  - pointillist: ``points(df, x="x", y="y", color="v", cmap="viridis", blend="replace")``:
    every point's colour is viridis at ``(v - min v) / (max v - min v)`` (a 256-entry
    lookup), each point a one-pixel square drawn in row order, the last point on a pixel
    wins (as matplotlib paints markers);
  - datashader: ``tf.shade(Canvas.points(df, "x", "y", agg=ds.mean("v")), cmap=viridis,
    how="linear")``: the mean of ``v`` over the points on each pixel, then viridis at the
    mean normalised between the least and greatest pixel mean;
  - matplotlib: ``Axes.scatter(x, y, c=v, cmap="viridis", s=one pixel, marker="s",
    linewidths=0)`` on a 1000x1000 Agg canvas, drawn (``fig.canvas.draw()``): each marker
    a one-pixel square filled with viridis at its normalised value, painted in row order;

  pointillist against datashader at 1 M and 10 M, against matplotlib at 1 M, on a pandas
  DataFrame (matplotlib: its columns as numpy arrays). The share of the pixels where two
  images agree (covered or not, and then within 4 levels a channel) is printed: with ``v``
  smooth, a pixel's mean and its last point's value differ by less than a pixel's width;
- chart: the medians of alternating rounds of pointillist (numpy arrays, a pandas and a
  polars DataFrame), datashader and matplotlib from 10 thousand to 100 million points
  (matplotlib to 3 million), for the one-pixel draw of one colour (as in datashader and
  matplotlib above) and for the colormapped draw (as in cmap), drawn log-log with
  matplotlib (Agg) into a PNG: the path
  given on the command line (an argument ending in ".png"), docs/images/python_compare.png
  by default. CHART_MAX (default 100000000) is the largest number of points; a side whose
  warm-up call takes more than 60 s is not run at larger sizes.

Usage (from the repository root, in a virtual environment with the package,
datashader, matplotlib, dask[dataframe,distributed], pandas, polars and pyarrow installed)::

    cargo build --profile python -p pointillist-plot --example time_render
    python crates/python/bench/compare.py [bindings] [datashader] [matplotlib] [dask] \\
        [frames] [cmap] [chart [out.png]]

With no mode, the first four run (frames, cmap and chart are run by name).
"""

import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import pointillist

W = H = 1000
RANGE = (0.0, 1.0)
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
TIME_RENDER = os.path.join(ROOT, "target", "python", "examples", "time_render")


def uniform(n, seed):
    """``n`` float32 values uniformly scattered in 0..1."""
    return np.random.default_rng(seed).random(n, dtype=np.float32)


def cpu_seconds():
    """User + system CPU seconds of this process and its waited-for children."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def timed(fn):
    """(wall seconds, CPU seconds, result) of one call."""
    c0, t0 = cpu_seconds(), time.perf_counter()
    result = fn()
    return time.perf_counter() - t0, cpu_seconds() - c0, result


def side_by_side(name, a_name, a, b_name, b, rounds):
    """Alternates ``a`` and ``b`` (each returns (wall, cpu)) ``rounds`` times after one
    warm-up call of each; prints and returns the medians."""
    a()
    b()
    rows = {a_name: [], b_name: []}
    for i in range(rounds):
        order = [(a_name, a), (b_name, b)] if i % 2 == 0 else [(b_name, b), (a_name, a)]
        for label, fn in order:
            rows[label].append(fn())
    wa = [w for w, _ in rows[a_name]]
    wb = [w for w, _ in rows[b_name]]
    ratio = statistics.median(x / y for x, y in zip(wa, wb))
    line = (
        f"| {name} | {a_name} {statistics.median(wa) * 1e3:.1f} ms "
        f"(CPU {statistics.median(c for _, c in rows[a_name]) * 1e3:.0f} ms) "
        f"| {b_name} {statistics.median(wb) * 1e3:.1f} ms "
        f"(CPU {statistics.median(c for _, c in rows[b_name]) * 1e3:.0f} ms) "
        f"| {ratio:.3f} | {rounds} |"
    )
    print(line, flush=True)
    return line


def points_call(x, y):
    def run():
        wall, cpu, _ = timed(
            lambda: pointillist.points(x, y, width=W, height=H, x_range=RANGE, y_range=RANGE)
        )
        return wall, cpu

    return run


def bindings():
    if not os.path.exists(TIME_RENDER):
        sys.exit(f"{TIME_RENDER} is missing: cargo build --profile python -p pointillist-plot "
                 "--example time_render")
    for n, rounds in ((1_000_000, 15), (10_000_000, 9)):
        x, y = uniform(n, 1), uniform(n, 2)
        with tempfile.TemporaryDirectory() as tmp:
            xf, yf = os.path.join(tmp, "x.f32"), os.path.join(tmp, "y.f32")
            x.astype("<f4").tofile(xf)
            y.astype("<f4").tofile(yf)

            def rust():
                # The second of two renders in one process (the first pays the page faults
                # of the fresh process, which a Python session has paid already).
                c0 = cpu_seconds()
                out = subprocess.run(
                    [TIME_RENDER, xf, yf, str(W), str(H), "2"],
                    check=True, capture_output=True, text=True,
                ).stdout.split()
                wall = float(out[-1])
                # CPU of the whole child process, both renders and the file reads.
                return wall, cpu_seconds() - c0

            side_by_side(f"bindings {n // 1_000_000} M", "python", points_call(x, y),
                         "rust", rust, rounds)


def datashader():
    import datashader as ds
    import datashader.transfer_functions as tf
    import pandas as pd

    canvas = ds.Canvas(plot_width=W, plot_height=H, x_range=RANGE, y_range=RANGE)
    for n, rounds in ((10_000_000, 7), (100_000_000, 5)):
        x, y = uniform(n, 1), uniform(n, 2)
        df = pd.DataFrame({"x": x, "y": y}, copy=False)

        def shade():
            wall, cpu, _ = timed(lambda: tf.shade(canvas.points(df, "x", "y")))
            return wall, cpu

        side_by_side(f"datashader {n // 1_000_000} M", "pointillist", points_call(x, y),
                     "datashader", shade, rounds)
        del df, x, y


def matplotlib():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = 1_000_000
    x, y = uniform(n, 1), uniform(n, 2)

    def scatter():
        def draw():
            fig = plt.figure(figsize=(W / 100, H / 100), dpi=100, facecolor="black")
            ax = fig.add_axes([0, 0, 1, 1])
            ax.set_axis_off()
            ax.set_xlim(*RANGE)
            ax.set_ylim(*RANGE)
            # A marker one pixel across: s is in points squared, 72 points an inch.
            ax.scatter(x, y, s=(72 / 100) ** 2, c="white", marker="s", linewidths=0)
            fig.canvas.draw()
            rgba = np.asarray(fig.canvas.buffer_rgba())
            plt.close(fig)
            return rgba

        wall, cpu, _ = timed(draw)
        return wall, cpu

    side_by_side("matplotlib 1 M", "pointillist", points_call(x, y), "matplotlib", scatter, 5)


def dask(rounds=int(os.environ.get("DASK_ROUNDS", "5"))):
    import dask.dataframe as dd
    import distributed
    import pandas as pd

    import pointillist.dask

    partitions, per = 20, 5_000_000

    def part(i):
        return pd.DataFrame({"x": uniform(per, 2 * i + 1), "y": uniform(per, 2 * i + 2)})

    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    with distributed.Client(cluster) as client:
        if os.environ.get("DASK_PLACEMENT") == "scheduler":
            df = dd.from_map(part, range(partitions)).persist()
        else:
            # Partition i made on worker i % 2: half the points in each worker's memory.
            workers = sorted(client.scheduler_info()["workers"])
            made = [client.submit(part, i, workers=[workers[i % 2]], allow_other_workers=False)
                    for i in range(partitions)]
            meta = pd.DataFrame({"x": uniform(0, 0), "y": uniform(0, 0)})
            df = dd.from_delayed(made, meta=meta, verify_meta=False).persist()
        distributed.wait(df)
        x = np.concatenate([uniform(per, 2 * i + 1) for i in range(partitions)])
        y = np.concatenate([uniform(per, 2 * i + 2) for i in range(partitions)])
        one = pointillist.points(x, y, width=W, height=H, x_range=RANGE, y_range=RANGE)
        two = pointillist.dask.points(df, width=W, height=H, x_range=RANGE, y_range=RANGE,
                                      client=client)
        assert np.array_equal(np.asarray(one), np.asarray(two)), "dask differs from one process"

        held = pointillist.dask._held(df, client)
        assert held is not None, "df is not persisted"
        print(f"# partitions a worker holds: {sorted(len(p) for p in held.values())}")

        def workers_cpu():
            return sum(client.run(cpu_seconds).values())

        def on_dask():
            # CPU: this process's (the client, and the scheduler LocalCluster runs here) and
            # the workers', read before and after the call.
            before = workers_cpu()
            wall, cpu, _ = timed(lambda: pointillist.dask.points(
                df, width=W, height=H, x_range=RANGE, y_range=RANGE, client=client))
            return wall, cpu + workers_cpu() - before

        side_by_side("dask 100 M", "dask 2 workers", on_dask, "one process", points_call(x, y),
                     rounds)
    cluster.close()


def frame_data(n):
    """x, y uniform in 0..1 (the same as the other modes') and ``v = (x + y) / 2``, float32."""
    x, y = uniform(n, 1), uniform(n, 2)
    v = ((x + y) * np.float32(0.5)).astype(np.float32)
    return x, y, v


def same_image(a, b, what):
    assert np.array_equal(np.asarray(a), np.asarray(b)), f"{what} differs from the arrays' draw"


def walled(fn):
    """A side for side_by_side: (wall, cpu) of ``fn()``."""
    def run():
        wall, cpu, _ = timed(fn)
        return wall, cpu

    return run


def shade_counts(canvas, df):
    import datashader.transfer_functions as tf

    return tf.shade(canvas.points(df, "x", "y"))


def shade_mean(canvas, df):
    import datashader as ds
    import datashader.transfer_functions as tf
    import matplotlib

    return tf.shade(canvas.points(df, "x", "y", agg=ds.mean("v")),
                    cmap=matplotlib.colormaps["viridis"], how="linear")


def scatter(x, y, **kw):
    """``Axes.scatter`` of one-pixel square markers on a 1000x1000 Agg canvas with a black
    background, drawn; the RGBA pixels, rows top to bottom."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(W / 100, H / 100), dpi=100, facecolor="black")
    ax = fig.add_axes([0, 0, 1, 1])
    ax.set_axis_off()
    ax.set_xlim(*RANGE)
    ax.set_ylim(*RANGE)
    # A marker one pixel across: s is in points squared, 72 points an inch.
    ax.scatter(x, y, s=(72 / 100) ** 2, marker="s", linewidths=0, **kw)
    fig.canvas.draw()
    rgba = np.array(fig.canvas.buffer_rgba())
    plt.close(fig)
    return rgba


def cmap_points(data, **kw):
    """pointillist's colormapped draw: by column names with a frame, ``x, y, color=v`` with
    ``data`` a tuple of arrays."""
    common = dict(width=W, height=H, x_range=RANGE, y_range=RANGE, cmap="viridis",
                  blend="replace")
    if isinstance(data, tuple):
        x, y, v = data
        return pointillist.points(x, y, color=v, **common)
    return pointillist.points(data, x="x", y="y", color="v", **common)


def agreement(a, a_covered, b, b_covered):
    """The share of pixels where two RGBA images agree: both uncovered, or both covered and
    within 4 levels in each of R, G and B."""
    a = np.asarray(a, dtype=np.int16)[..., :3]
    b = np.asarray(b, dtype=np.int16)[..., :3]
    close = (np.abs(a - b) <= 4).all(axis=-1)
    same = (a_covered == b_covered) & (~a_covered | close)
    return same.mean()


def rgb_covered(img):
    """Covered pixels of an image on opaque black: no viridis colour is black."""
    return np.asarray(img)[..., :3].any(axis=-1)


def datashader_rgba(img):
    """A datashader Image as RGBA bytes, rows top to bottom, and its covered pixels."""
    rgba = np.asarray(img.data).view(np.uint8).reshape(H, W, 4)[::-1]
    return rgba, rgba[..., 3] > 0


def frames():
    import datashader as ds
    import pandas as pd
    import polars as pl
    import pyarrow as pa

    n, rounds = 10_000_000, 9
    x, y = uniform(n, 1), uniform(n, 2)
    df = pd.DataFrame({"x": x, "y": y}, copy=False)
    pf = pl.DataFrame({"x": x, "y": y})
    table = pa.table({"x": x, "y": y})
    print(f"# pandas {pd.__version__}, polars {pl.__version__}, pyarrow {pa.__version__}, "
          f"datashader {ds.__version__}; polars chunks {pf.n_chunks()}, "
          f"pyarrow batches {len(table.to_batches())}")

    def draw(data):
        if data is None:
            return pointillist.points(x, y, width=W, height=H, x_range=RANGE, y_range=RANGE)
        return pointillist.points(data, x="x", y="y", width=W, height=H, x_range=RANGE,
                                  y_range=RANGE)

    arrays = draw(None)
    for label, data in (("pandas", df), ("polars", pf), ("pyarrow", table)):
        same_image(draw(data), arrays, f"the {label} frame's draw")
    for label, data in (("pandas", df), ("polars", pf), ("pyarrow", table)):
        side_by_side(f"frames {n // 1_000_000} M, {label}", f"{label} frame",
                     walled(lambda data=data: draw(data)), "numpy arrays",
                     walled(lambda: draw(None)), rounds)
    canvas = ds.Canvas(plot_width=W, plot_height=H, x_range=RANGE, y_range=RANGE)
    side_by_side(f"frames {n // 1_000_000} M, pandas", "pointillist", walled(lambda: draw(df)),
                 "datashader", walled(lambda: shade_counts(canvas, df)), rounds)


def cmap():
    import datashader as ds
    import matplotlib as mpl
    import pandas as pd

    print(f"# datashader {ds.__version__}, matplotlib {mpl.__version__}, "
          f"pandas {pd.__version__}")
    canvas = ds.Canvas(plot_width=W, plot_height=H, x_range=RANGE, y_range=RANGE)
    for n, rounds in ((1_000_000, 9), (10_000_000, 7)):
        x, y, v = frame_data(n)
        df = pd.DataFrame({"x": x, "y": y, "v": v}, copy=False)
        ours = cmap_points(df)
        same_image(ours, cmap_points((x, y, v)), "the pandas frame's colormapped draw")
        theirs, covered = datashader_rgba(shade_mean(canvas, df))
        print(f"# {n // 1_000_000} M: pixels where pointillist and datashader agree: "
              f"{agreement(ours, rgb_covered(ours), theirs, covered):.4f}")
        side_by_side(f"cmap {n // 1_000_000} M", "pointillist", walled(lambda: cmap_points(df)),
                     "datashader", walled(lambda: shade_mean(canvas, df)), rounds)
        if n == 1_000_000:
            mine = scatter(x, y, c=v, cmap="viridis")
            print(f"# {n // 1_000_000} M: pixels where pointillist and matplotlib agree: "
                  f"{agreement(ours, rgb_covered(ours), mine, rgb_covered(mine)):.4f}")
            side_by_side(f"cmap {n // 1_000_000} M", "pointillist",
                         walled(lambda: cmap_points(df)), "matplotlib",
                         walled(lambda: scatter(x, y, c=v, cmap="viridis")), 5)
        del df, x, y, v, ours


def race(sides, rounds):
    """Times every side (name -> function) ``rounds`` times after one warm-up call each, the
    order rotated round by round; returns {name: (median wall, median of the per-round ratios
    to the first side, warm-up wall)}."""
    warm = {}
    for name, fn in sides.items():
        t0 = time.perf_counter()
        fn()
        warm[name] = time.perf_counter() - t0
    names = list(sides)
    walls = {name: [] for name in names}
    for i in range(rounds):
        k = i % len(names)
        order = names[k:] + names[:k]
        if i % 2:
            order.reverse()
        for name in order:
            t0 = time.perf_counter()
            sides[name]()
            walls[name].append(time.perf_counter() - t0)
    first = walls[names[0]]
    return {name: (statistics.median(w), statistics.median(a / b for a, b in zip(w, first)),
                   warm[name]) for name, w in walls.items()}


CHART_SIDES = ("pointillist, numpy", "pointillist, pandas", "pointillist, polars",
               "datashader", "matplotlib")
MATPLOTLIB_MAX = 3_000_000
TOO_SLOW = 60.0


def chart():
    import datashader as ds
    import matplotlib as mpl
    import pandas as pd
    import polars as pl

    out = next((a for a in sys.argv[1:] if a.endswith(".png")),
               os.path.join("docs", "images", "python_compare.png"))
    largest = int(os.environ.get("CHART_MAX", "100000000"))
    sizes = [n for n in (10_000, 30_000, 100_000, 300_000, 1_000_000, 3_000_000, 10_000_000,
                         30_000_000, 100_000_000) if n <= largest]
    canvas = ds.Canvas(plot_width=W, plot_height=H, x_range=RANGE, y_range=RANGE)
    versions = (f"datashader {ds.__version__}, matplotlib {mpl.__version__}, "
                f"pandas {pd.__version__}, polars {pl.__version__}")
    print(f"# {versions}")
    print("| draw | points | " + " | ".join(CHART_SIDES) + " | rounds |")
    print("|---|---|" + "---|" * len(CHART_SIDES) + "---|")
    print("(each cell: median wall, and in brackets the median of the per-round ratios to "
          "pointillist on numpy arrays)")
    dropped = set()
    results = {"one colour": {}, "viridis": {}}
    for n in sizes:
        rounds = 7 if n <= 1_000_000 else 5 if n <= 10_000_000 else 3
        x, y, v = frame_data(n)
        df = pd.DataFrame({"x": x, "y": y, "v": v}, copy=False)
        pf = pl.DataFrame({"x": x, "y": y, "v": v})
        plain = dict(width=W, height=H, x_range=RANGE, y_range=RANGE)
        same_image(pointillist.points(pf, x="x", y="y", **plain),
                   pointillist.points(x, y, **plain), "the polars frame's draw")
        same_image(cmap_points(pf), cmap_points((x, y, v)), "the polars frame's colormapped draw")
        panels = {
            "one colour": {
                "pointillist, numpy": lambda: pointillist.points(x, y, **plain),
                "pointillist, pandas": lambda: pointillist.points(df, x="x", y="y", **plain),
                "pointillist, polars": lambda: pointillist.points(pf, x="x", y="y", **plain),
                "datashader": lambda: shade_counts(canvas, df),
                "matplotlib": lambda: scatter(x, y, c="white"),
            },
            "viridis": {
                "pointillist, numpy": lambda: cmap_points((x, y, v)),
                "pointillist, pandas": lambda: cmap_points(df),
                "pointillist, polars": lambda: cmap_points(pf),
                "datashader": lambda: shade_mean(canvas, df),
                "matplotlib": lambda: scatter(x, y, c=v, cmap="viridis"),
            },
        }
        for panel, sides in panels.items():
            sides = {name: fn for name, fn in sides.items()
                     if (panel, name) not in dropped
                     and not (name == "matplotlib" and n > MATPLOTLIB_MAX)}
            got = race(sides, rounds)
            results[panel][n] = got
            for name, (_, _, warm) in got.items():
                if warm > TOO_SLOW:
                    dropped.add((panel, name))
            cells = " | ".join(
                f"{got[name][0] * 1e3:.1f} ms ({got[name][1]:.2f})" if name in got else "-"
                for name in CHART_SIDES)
            print(f"| {panel} | {n:,} | {cells} | {rounds} |", flush=True)
        del df, pf, x, y, v, panels

    mpl.use("Agg")
    import matplotlib.pyplot as plt

    model = cpu_model()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6), dpi=90, sharey=True)
    styles = {"pointillist, numpy": ("C0", "o", "-"), "pointillist, pandas": ("C0", "s", "--"),
              "pointillist, polars": ("C0", "^", ":"), "datashader": ("C1", "D", "-"),
              "matplotlib": ("C2", "v", "-")}
    titles = {"one colour": "one colour, additive (datashader: count + shade)",
              "viridis": "colour from a value, viridis (datashader: mean + shade)"}
    for ax, (panel, by_n) in zip(axes, results.items()):
        for name in CHART_SIDES:
            ns = [n for n in sizes if n in by_n and name in by_n[n]]
            if not ns:
                continue
            color, marker, line = styles[name]
            ax.loglog(ns, [by_n[n][name][0] for n in ns], color=color, marker=marker,
                      linestyle=line, label=name, markersize=4)
        ax.set_title(titles[panel], fontsize=9)
        ax.set_xlabel("points")
        ax.grid(True, which="major", alpha=0.4)
        ax.grid(True, which="minor", alpha=0.15)
    axes[0].set_ylabel("median wall time (s)")
    axes[0].legend(fontsize=8)
    fig.suptitle(
        f"1000x1000 image, uniform float32 points: median of 3 to 7 alternating rounds\n"
        f"{model}, {os.cpu_count()} cores (shared), pointillist lanes {pointillist.lanes()}, "
        f"{time.strftime('%Y-%m-%d', time.gmtime())}; {versions}", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(f"# wrote {out} ({os.path.getsize(out) // 1024} KB)")


def cpu_model():
    return next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo")
                 if line.startswith("model name")), platform.processor())


MODES = ("bindings", "datashader", "matplotlib", "dask", "frames", "cmap", "chart")


def main():
    which = [a for a in sys.argv[1:] if not a.endswith(".png")]
    which = which or ["bindings", "datashader", "matplotlib", "dask"]
    for name in which:
        if name not in MODES:
            sys.exit(f"unknown mode {name!r}: the modes are {', '.join(MODES)}")
    model = cpu_model()
    print(f"# {model}, {os.cpu_count()} cores, pointillist lanes {pointillist.lanes()}, "
          f"Python {platform.python_version()}, numpy {np.__version__}")
    print("| case | A: median wall (CPU) | B: median wall (CPU) | median A/B | rounds |")
    print("|---|---|---|---|---|")
    for name in which:
        globals()[name]()


if __name__ == "__main__":
    main()
