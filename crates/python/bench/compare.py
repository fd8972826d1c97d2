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
  (default 5) sets the rounds.

Usage (from the repository root, in a virtual environment with the package,
datashader, matplotlib, dask[dataframe,distributed] and pandas installed)::

    cargo build --profile python -p pointillist-plot --example time_render
    python crates/python/bench/compare.py [bindings] [datashader] [matplotlib] [dask]
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


def main():
    which = sys.argv[1:] or ["bindings", "datashader", "matplotlib", "dask"]
    model = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo")
                  if line.startswith("model name")), platform.processor())
    print(f"# {model}, {os.cpu_count()} cores, pointillist lanes {pointillist.lanes()}, "
          f"Python {platform.python_version()}, numpy {np.__version__}")
    print("| case | A: median wall (CPU) | B: median wall (CPU) | median A/B | rounds |")
    print("|---|---|---|---|---|")
    for name in which:
        globals()[name]()


if __name__ == "__main__":
    main()
