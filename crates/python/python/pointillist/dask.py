"""Exact distributed rendering of a Dask DataFrame.

:func:`points` draws the rows of a Dask DataFrame on the workers of a ``dask.distributed``
cluster and returns the same array, bit for bit, as :func:`pointillist.points` on all the rows
in order. Two strategies, chosen by the blend:

- **Draws of one colour** ("add", "max" or "replace" with one colour, no depth, no texture)
  give each pixel a colour that depends only on how many points cover it. Each partition
  counts its points per pixel (one byte a pixel, saturating at 255, where every count from
  255 up gives the same colour); the counts are added, first among the partitions each worker
  holds, and mapped to colours once, on the client. Addition commutes, so this equals drawing
  every row in order.
- **"add" and "max" without depth** commute. Each partition is drawn on its worker onto a zero
  target; the partial images are combined with the blend's exact operator (8-bit saturating
  addition, or the maximum, channel by channel) in a tree of ``split_every`` images a node,
  first among the partitions each worker holds, and the clear colour is combined once at the
  end. Saturating addition of non-negative numbers is associative and commutative, so this
  equals drawing every row in order onto the cleared target.
- **"alpha", "replace" (of several colours), and any draw with depth** depend on the order of the points. The
  target is cut into screen tiles (sort-first): each partition sends each of its points, as
  its vertex with its index, to every tile its square overlaps (decided by the same per-point
  rule the draw uses); each tile draws its points in index order on a target whose viewport
  is the tile, so every pixel sees the operations of the full draw in the same order; the
  tiles are assembled on the client.

The data-to-pixel formula, the vertices and the states are those of :func:`pointillist.points`
(one implementation, in Rust, runs on every worker). The workers need the ``pointillist``
package installed, like any library a Dask task calls.

Example, on a real cluster::

    from dask.distributed import Client
    import dask.dataframe as dd
    import pointillist.dask

    client = Client("tcp://scheduler:8786")
    df = dd.read_parquet("s3://bucket/points/*.parquet", columns=["x", "y", "c"])
    img = pointillist.dask.points(df, x="x", y="y", color="c", width=2000, height=2000,
                                  x_range=(0, 1), y_range=(0, 1), blend="alpha")
"""

import functools

import numpy

from . import _native
from ._image import Image

__all__ = ["points"]

_BLENDS = ("add", "alpha", "max", "replace")


def points(
    df,
    x="x",
    y="y",
    *,
    size=1.0,
    color=0xFFFFFFFF,
    z=None,
    width,
    height,
    blend="add",
    x_range=None,
    y_range=None,
    clear=0xFF000000,
    texture=None,
    tile_size=256,
    split_every=8,
    client=None,
):
    """Draw the rows of Dask DataFrame ``df`` on a ``dask.distributed`` cluster, exactly.

    Returns what ``pointillist.points(x, y, size=..., color=..., z=..., ...)`` returns for all
    the rows of ``df`` in order, bit for bit (see the module's description for how).

    Parameters
    ----------
    df : dask.dataframe.DataFrame
    x, y : str
        Column names of the positions.
    size : str or float
        A column of sizes in pixels, or one size for every point.
    color : str or int
        A column of uint32 D3DCOLORs (0xAARRGGBB), or one D3DCOLOR.
    z : str or None
        A column of depths in 0..1: the depth test is on (and the tile strategy is used).
    width, height, blend, x_range, y_range, clear, texture
        As in :func:`pointillist.points`.
    tile_size : int or (int, int)
        The side of the screen tiles of the order-dependent strategy, in pixels.
    split_every : int
        Partial images (or counts) combined per node of the reduction tree.
    client : dask.distributed.Client or None
        The client to compute on; by default the active one (``distributed.default_client``),
        or Dask's local scheduler when there is none.

    Raises
    ------
    ValueError, TypeError
        As :func:`pointillist.points` does (a NaN names its partition and row), and for a
        column that is not in ``df``.
    """
    import dask

    if blend not in _BLENDS:
        raise ValueError(
            f'unknown blend "{blend}" (expected "add", "alpha", "max" or "replace")'
        )
    tw, th = (tile_size, tile_size) if numpy.ndim(tile_size) == 0 else tile_size
    rects = _native._tiles(width, height, int(tw), int(th))
    if int(split_every) < 2:
        raise ValueError(f"split_every {split_every} must be at least 2")
    columns = {"x": x, "y": y}
    for key, value in (("size", size), ("color", color), ("z", z)):
        if isinstance(value, str):
            columns[key] = value
    missing = [c for c in columns.values() if c not in df.columns]
    if missing:
        raise ValueError(
            f"column {missing[0]!r} is not in the DataFrame (its columns: "
            f"{', '.join(map(str, df.columns))})"
        )
    if z is not None and "z" not in columns:
        raise TypeError("z must be a column name or None")
    constants = {
        "size": None if "size" in columns else size,
        "color": None if "color" in columns else color,
    }
    common = dict(width=width, height=height, blend=blend, x_range=x_range, y_range=y_range)
    # Checks the scalar arguments (clear, ranges, texture, size, color) here, before any task.
    _native.points(
        numpy.zeros(0, numpy.float32),
        numpy.zeros(0, numpy.float32),
        size=1.0 if constants["size"] is None else constants["size"],
        color=0 if constants["color"] is None else constants["color"],
        clear=clear,
        texture=texture,
        backend="cpu",
        z=None,
        **common,
    )
    client = _client(client)
    parts = df.to_delayed()
    # Fresh keys every call (pure=False): a call is never answered by the result of an
    # earlier one that the scheduler has not yet released.
    task = lambda fn, **kw: dask.delayed(fn, pure=False, **kw)  # noqa: E731
    layout_args = _layout_args(constants, columns, common, clear, texture)
    counted = (
        z is None
        and constants["color"] is not None
        and _native._counts(*layout_args[:2], **layout_args[2]) is not None
    )
    if counted:
        groups = [
            [task(_count)(parts[p], p, columns, constants, common, clear, texture) for p in g]
            for g in _by_worker(df, client)
        ]
        counts = _reduce(task, groups, _add_counts, split_every)
        total = numpy.asarray(_compute(counts, client))
        return _native._from_counts(total, *layout_args[:2], **layout_args[2]).view(Image)
    if blend in ("add", "max") and z is None:
        groups = [
            [task(_partial)(parts[p], p, columns, constants, common, texture) for p in g]
            for g in _by_worker(df, client)
        ]
        images = _reduce(task, groups, functools.partial(_combine, blend=blend), split_every)
        result = task(_finish)(images, blend, clear)
    else:
        size_const = constants["size"]
        tiling = dict(common, tile_width=int(tw), tile_height=int(th))
        binned = [
            task(_bin, nout=len(rects))(part, p, columns, constants, tiling)
            for p, part in enumerate(parts)
        ]
        layout = dict(size=None if size_const is None else float(size_const), depth=z is not None)
        tiles = [
            task(_tile)([b[t] for b in binned], rect, layout, common, clear, texture)
            for t, rect in enumerate(rects)
        ]
        result = task(_assemble)(tiles, rects, width, height)
    return _compute(result, client).view(Image)


def _layout_args(constants, columns, common, clear, texture):
    """Empty columns with the draw's layout, and the keywords, for ``_native._counts`` and
    ``_native._from_counts``."""
    empty = numpy.zeros(0, numpy.float32)
    size = empty if "size" in columns else constants["size"]
    kw = dict(common, size=size, color=constants["color"], clear=clear, texture=texture)
    return empty, empty, kw


def _client(client):
    """``client``, else the active ``dask.distributed`` client, else None (local scheduler)."""
    if client is None:
        try:
            from distributed import default_client

            client = default_client()
        except (ImportError, ValueError):
            client = None
    return client


def _by_worker(df, client):
    """The partition indices of ``df`` grouped by the worker that holds them (in order within
    a group), where ``df`` is persisted on ``client``; otherwise one group of them all."""
    n = df.npartitions
    where = {}
    if client is not None:
        try:
            # A persisted collection's futures: one a partition, keyed (name, partition).
            futures = client.futures_of(df)
            if sorted(f.key[1] for f in futures) == list(range(n)):
                who = client.who_has(futures)
                where = {f.key[1]: who[f.key][0] for f in futures if who.get(f.key)}
        except Exception:  # any failure only loses locality
            where = {}
    groups = {}
    for p in range(n):
        groups.setdefault(where.get(p), []).append(p)
    return list(groups.values())


def _reduce(task, groups, combine, split_every):
    """One task combining every item of ``groups`` (lists of tasks): a tree of ``split_every``
    items a node within each group (whose items are on one worker), then across groups."""

    def tree(items):
        while len(items) > 1:
            items = [
                task(combine)(items[i : i + split_every])
                for i in range(0, len(items), split_every)
            ]
        return items[0]

    return tree([tree(g) for g in groups if g])


def _compute(result, client):
    if client is None:
        return result.compute()
    return client.compute(result).result()


def _columns(part, p, columns, constants):
    """The numpy columns of partition ``p`` (read in place where pandas holds numpy)."""
    get = {k: part[c].to_numpy() for k, c in columns.items()}
    size = get.get("size", constants["size"])
    color = get.get("color", constants["color"])
    return get["x"], get["y"], get.get("z"), size, color


def _named(p, error):
    """``error`` with the partition it came from."""
    return type(error)(f"partition {p}: {error}")


def _partial(part, p, columns, constants, common, texture):
    x, y, _, size, color = _columns(part, p, columns, constants)
    try:
        image = _native._partial(x, y, size=size, color=color, texture=texture, **common)
    except (ValueError, TypeError) as e:
        raise _named(p, e) from None
    return numpy.asarray(image)


def _count(part, p, columns, constants, common, clear, texture):
    x, y, _, size, color = _columns(part, p, columns, constants)
    try:
        counts = _native._counts(
            x, y, size=size, color=color, clear=clear, texture=texture, **common
        )
    except (ValueError, TypeError) as e:
        raise _named(p, e) from None
    return counts


def _add_counts(counts):
    out = numpy.array(counts[0])
    for c in counts[1:]:
        _native._add_counts(out, c)
    return out


def _combine(images, blend):
    out = numpy.array(images[0])
    for image in images[1:]:
        _native._combine(out, image, blend)
    return out


def _finish(image, blend, clear):
    out = numpy.array(image)
    _native._finish(out, blend, clear)
    return out


def _bin(part, p, columns, constants, tiling):
    x, y, z, size, color = _columns(part, p, columns, constants)
    try:
        bins = _native._bin(x, y, size=size, color=color, z=z, first_index=p << 40, **tiling)
    except (ValueError, TypeError) as e:
        raise _named(p, e) from None
    return tuple(bins)


def _tile(pieces, rect, layout, common, clear, texture):
    """Draws one tile from the pieces every partition sent it, in index order."""
    vertices = numpy.concatenate([v for v, _ in pieces])
    index = numpy.concatenate([i for _, i in pieces])
    if index.size > 1 and not numpy.all(index[1:] > index[:-1]):
        vertices = vertices[numpy.argsort(index, kind="stable")]
    common = {k: v for k, v in common.items() if k not in ("x_range", "y_range")}
    image = _native._render_tile(
        vertices, tuple(rect), clear=clear, texture=texture, **layout, **common
    )
    return numpy.asarray(image)


def _assemble(tiles, rects, width, height):
    out = numpy.empty((height, width, 4), numpy.uint8)
    for tile, (x0, y0, x1, y1) in zip(tiles, rects):
        out[y0:y1, x0:x1] = tile
    return out
