"""Exact distributed rendering of a Dask DataFrame.

:func:`points` draws the rows of a Dask DataFrame on the workers of a ``dask.distributed``
cluster and returns the same array, bit for bit, as :func:`pointillist.points` on all the rows
in order. Three strategies, chosen by the blend:

- **Draws of one colour** ("add", "max" or "replace" with one colour, no depth, no texture)
  give each pixel a colour that depends only on how many points cover it. Each partition
  counts its points per pixel (one byte a pixel, saturating at 255, where every count from
  255 up gives the same colour); the counts are added, and mapped to colours once, on the
  client. Addition commutes, so this equals drawing every row in order.
- **"add" and "max" without depth** commute. Each partition is drawn on its worker onto a zero
  target; the partial images are combined with the blend's exact operator (8-bit saturating
  addition, or the maximum, channel by channel), and the clear colour is combined once at the
  end. Saturating addition of non-negative numbers is associative and commutative, so this
  equals drawing every row in order onto the cleared target.
- **"alpha", "replace" (of several colours), and any draw with depth** depend on the order of
  the points. The target is cut into screen tiles (sort-first): each partition sends each of
  its points, as its vertex with its index, to every tile its square overlaps (decided by the
  same per-point rule the draw uses); each tile draws its points in index order on a target
  whose viewport is the tile, so every pixel sees the operations of the full draw in the same
  order; the tiles are assembled on the client.

For the first two, a ``df`` persisted on the client (``df = df.persist()``, every partition
in a worker's memory) runs one task on each worker over the partitions it holds (found with
``who_has``; no task graph is built): it counts them all into one array, or combines their
images, and the client adds the workers' results as they arrive (beyond ``split_every``
workers, tasks on the workers combine them first). Any other ``df`` (not persisted, or
derived from a persisted one) is computed by its graph: one task a partition, reduced in a
tree of ``split_every`` a node. A task draws on as many threads as its worker has, not one a
core: worker processes of one thread each, one a core, would otherwise compete for the cores.

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

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, Callable, Optional, Sequence, Tuple, Union

import numpy
import numpy.typing as npt

from . import _column, _native, _shade
from ._image import Image
from ._native import Plot

if TYPE_CHECKING:
    from ._native import _Behaviour as Behaviour
    from ._native import _Blend as Blend
    from ._native import _Marker as Marker
    from ._native import _SizeUnits as SizeUnits

__all__ = ["points"]


def points(
    df: Any,
    x: str = "x",
    y: str = "y",
    *,
    size: Union[str, float] = 1.0,
    color: Union[str, int] = 0xFFFFFFFF,
    z: Optional[str] = None,
    width: int,
    height: int,
    blend: Blend = "add",
    x_range: Optional[Tuple[float, float]] = None,
    y_range: Optional[Tuple[float, float]] = None,
    clear: int = 0xFF000000,
    texture: Optional[npt.NDArray[numpy.uint8]] = None,
    tile_size: Union[int, Tuple[int, int]] = 256,
    split_every: int = 8,
    client: Any = None,
    behaviour: Behaviour = None,
    cmap: _shade.Cmap = None,
    how: Optional[str] = None,
    vmin: Optional[float] = None,
    vmax: Optional[float] = None,
    color_key: Optional[Mapping[Any, Any]] = None,
    marker: Marker = "square",
    size_units: SizeUnits = "pixels",
) -> Image:
    """Draw the rows of Dask DataFrame ``df`` on a ``dask.distributed`` cluster, exactly.

    Returns what ``pointillist.points(x, y, size=..., color=..., z=..., ...)`` returns for all
    the rows of ``df`` in order, bit for bit (see the module's description for how).

    Parameters
    ----------
    df : dask.dataframe.DataFrame
        When it is persisted (``df.persist()``), draws of one colour and "add" and "max" draws
        run one task a worker, without a task graph (see the module's description).
    x, y : str
        Column names of the positions.
    size : str or float
        A column of sizes in pixels (in x's data units with ``size_units="data"``), or one size
        for every point.
    color : str or int
        A column of uint32 D3DCOLORs (0xAARRGGBB), or one D3DCOLOR.
    z : str or None
        A column of depths in 0..1: the depth test is on (and the tile strategy is used).
    width, height, blend, x_range, y_range, clear, texture, behaviour, marker, size_units
        As in :func:`pointillist.points`; every partition and tile draws with the same
        device behaviour switches.
    tile_size : int or (int, int)
        The side of the screen tiles of the order-dependent strategy, in pixels.
    split_every : int
        Partial images (or counts) combined per node of the reduction tree (of the partitions
        of a ``df`` that is not persisted, or of the workers' results of one that is).
    client : dask.distributed.Client or None
        The client to compute on; by default the active one (``distributed.default_client``),
        or Dask's local scheduler when there is none.
    cmap, how, vmin, vmax, color_key
        Colour from values, as in :func:`pointillist.points`. With ``color`` a column: each
        partition computes its points' colours with the same ``vmin`` and ``vmax`` (by
        default the column's least and greatest, computed first, one pass over the column),
        so that the result is that of :func:`pointillist.points` on all the rows; ``how``
        "linear" or "log" (not "eq_hist", which needs every value); a column of categories
        needs ``color_key``. With one ``color`` (a constant) and a counted draw: the counts of
        all the partitions, added, shaded as :func:`pointillist.points` shades them
        (datashader's ``tf.shade``).

    Raises
    ------
    ValueError, TypeError
        As :func:`pointillist.points` does (a NaN names its partition and row), and for a
        column that is not in ``df``.
    """
    import dask

    # The plot's arguments, checked once (in Rust) before any task: the workers get this
    # Plot, pickled.
    plot = Plot(
        width, height, blend=blend, x_range=x_range, y_range=y_range, clear=clear,
        texture=texture, behaviour=behaviour, marker=marker, size_units=size_units,
    )
    sides: Any = (tile_size, tile_size) if numpy.ndim(tile_size) == 0 else tile_size
    tw, th = sides
    rects = _native._tiles(plot, int(tw), int(th))
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
    constants: dict[str, Any] = {
        "size": None if "size" in columns else size,
        "color": None if "color" in columns else color,
    }
    # The constant size and colour, checked as points checks them, before any task.
    empty = numpy.zeros(0, numpy.float32)
    _native._check(
        plot,
        (
            empty,
            empty,
            None,
            1.0 if constants["size"] is None else constants["size"],
            0 if constants["color"] is None else constants["color"],
        ),
    )
    shading = any(v is not None for v in (cmap, how, vmin, vmax, color_key))
    if color_key is not None and constants["color"] is not None:
        raise TypeError("color_key needs color to be a column of categories")
    client = _client(client)
    if shading and constants["color"] is None:
        constants["shade"] = _values_shade(
            df, str(color), client, cmap=cmap, how=how, vmin=vmin, vmax=vmax,
            color_key=color_key,
        )
    # Fresh keys every call (pure=False): a call is never answered by the result of an
    # earlier one that the scheduler has not yet released.
    task = lambda fn, **kw: dask.delayed(fn, pure=False, **kw)  # noqa: E731
    # Empty columns with the draw's layout (a size column or not, a colour or not).
    layout: Any = (empty, empty, None, empty if "size" in columns else size, constants["color"])
    counted = (
        z is None
        and constants["color"] is not None
        and _native._counts(plot, layout) is not None
    )
    if shading and constants["color"] is not None and not counted:
        raise ValueError(
            'only a draw of one colour is shaded from its counts: a constant color, blend '
            '"add", "max" or "replace", no z, no texture'
        )
    commuting = counted or (plot.commutes and z is None)
    held = _held(df, client) if commuting else None
    if counted:
        args = (columns, constants, plot)
        if held is not None:
            # Persisted: one task a worker over the partitions it holds, no graph to build.
            total = _gather_sum(
                client, _count_held, held.items(), args, _add_counts, _native._add_counts,
                split_every,
            )
        else:
            parts = df.to_delayed()
            counts = [task(_count)(parts[p], p, *args) for p in range(len(parts))]
            total = _compute(_reduce(task, counts, _add_counts, split_every), client)
        total = numpy.asarray(total)
        if shading:
            shaded = _shade.shade_counts(total, plot.clear, cmap, how, vmin, vmax)
            return shaded.view(Image)._located(plot, x, y)
        counted_image = _native._from_counts(plot, total, layout).view(Image)
        return counted_image._located(plot, x, y)
    if plot.commutes and z is None:
        args = (columns, constants, plot)
        if held is not None:
            combined = _gather_sum(
                client, _partial_held, held.items(), args,
                functools.partial(_combine, plot=plot),
                functools.partial(_native._combine, plot=plot), split_every,
            )
            return _finish(combined, plot).view(Image)._located(plot, x, y)
        parts = df.to_delayed()
        images = [task(_partial)(parts[p], p, *args) for p in range(len(parts))]
        combine = functools.partial(_combine, plot=plot)
        result = task(_finish)(_reduce(task, images, combine, split_every), plot)
    else:
        size_const = constants["size"]
        tile = (int(tw), int(th))
        parts = df.to_delayed()
        binned = [
            task(_bin, nout=len(rects))(part, p, columns, constants, plot, tile)
            for p, part in enumerate(parts)
        ]
        vertex_layout = dict(
            size=None if size_const is None else float(size_const), depth=z is not None
        )
        tiles = [
            task(_tile)([b[t] for b in binned], rect, vertex_layout, plot)
            for t, rect in enumerate(rects)
        ]
        result = task(_assemble)(tiles, rects, width, height)
    return _compute(result, client).view(Image)._located(plot, x, y)


def _client(client: Any) -> Any:
    """``client``, else the active ``dask.distributed`` client, else None (local scheduler)."""
    if client is None:
        try:
            from distributed import default_client

            client = default_client()
        except (ImportError, ValueError):
            client = None
    return client


def _held(df: Any, client: Any) -> Optional[dict]:
    """Where ``df`` is persisted on ``client`` with every partition in a worker's memory: its
    partitions as ``{worker: [(index, future), ...]}``, in partition order on each worker;
    otherwise None (the partitions are computed by ``df``'s graph)."""
    if client is None:
        return None
    try:
        from distributed import Future

        expr = getattr(df, "expr", None)
        if expr is not None:
            # dask-expr: a persisted collection is a FromGraph of the futures, under their
            # own keys, in partition order; anything derived from it is another expression.
            if type(expr).__name__ != "FromGraph":
                return None
            keys, layer = list(expr.operand("keys")), expr.operand("layer")
        else:  # the legacy DataFrame: its graph maps its keys to the futures
            keys, layer = list(df.__dask_keys__()), df.__dask_graph__()
        ordered = [layer.get(k) for k in keys]
        if len(ordered) != df.npartitions or not all(isinstance(f, Future) for f in ordered):
            return None
        if any(f.status != "finished" for f in ordered):
            return None
        who = client.who_has(ordered)
        held: dict = {}
        for p, f in enumerate(ordered):
            workers = who.get(f.key)
            if not workers:
                return None
            held.setdefault(workers[0], []).append((p, f))
        return held or None
    except Exception:  # anything unexpected: the graph computes it as well
        return None


def _gather_sum(
    client: Any, fn: Callable[..., Any], held: Any, args: tuple,
    combine: Callable[..., Any], add: Callable[..., Any], split_every: int,
) -> numpy.ndarray:
    """One task ``fn(*args, indices, *partitions)`` for each ``(worker, [(index, future),
    ...])`` of ``held`` (``_held``'s items), on that worker, each returning an array; the
    arrays combined into one on the client, each added with ``add(dst, src)`` (in place) as
    it arrives. Beyond ``split_every`` tasks, tasks ``combine(arrays)`` on the workers first
    reduce them ``split_every`` a node."""
    from distributed import as_completed

    tasks = [
        client.submit(
            fn, *args, [p for p, _ in parts], *[f for _, f in parts],
            workers=[worker],
            # Should the worker leave, the task runs where the partitions are recomputed.
            allow_other_workers=True,
            pure=False,
        )
        for worker, parts in held
    ]
    while len(tasks) > split_every:
        tasks = [
            client.submit(combine, tasks[i : i + split_every], pure=False)
            for i in range(0, len(tasks), split_every)
        ]
    out: Any = None
    # Added as they arrive: the first arrays travel while the last task runs.
    for _, array in as_completed(tasks, with_results=True):
        if out is None:
            # Arrays received from a worker may be read-only views of the message.
            out = numpy.require(array, requirements=["C", "W"])
        else:
            add(out, array)
    return out


def _reduce(task: Callable[..., Any], items: list, combine: Callable[..., Any], split_every: int) -> Any:
    """One task combining ``items`` (tasks): a tree of ``split_every`` items a node."""
    while len(items) > 1:
        items = [
            task(combine)(items[i : i + split_every]) for i in range(0, len(items), split_every)
        ]
    return items[0]


def _compute(result: Any, client: Any) -> numpy.ndarray:
    if client is None:
        return result.compute()
    return client.compute(result).result()


def _columns(part: Any, p: int, columns: dict, constants: dict) -> tuple:
    """The columns ``(x, y, z, size, color)`` of partition ``p``, numpy arrays (read in place
    where pandas holds numpy; a nullable column converted once, refused with a null, as
    :func:`pointillist.points` reads a DataFrame's) or constants."""
    try:
        get = {k: _column(k, c, part[c]) for k, c in columns.items()}
    except (ValueError, TypeError) as e:
        raise _named(p, e) from None
    size = get.get("size", constants["size"])
    color = get.get("color", constants["color"])
    shade = constants.get("shade")
    if shade is not None:
        try:
            color = _shade.colors_of("color", color, **shade)
        except (ValueError, TypeError) as e:
            raise _named(p, e) from None
    return get["x"], get["y"], get.get("z"), size, color


def _values_shade(
    df: Any,
    name: str,
    client: Any,
    *,
    cmap: _shade.Cmap,
    how: Optional[str],
    vmin: Optional[float],
    vmax: Optional[float],
    color_key: Optional[Mapping[Any, Any]],
) -> dict:
    """The arguments of :func:`_shade.colors_of` that colour every partition's column
    ``name`` as all its values together would be: numbers between one ``vmin`` and ``vmax``
    (the column's least and greatest unless given), categories by ``color_key``."""
    how = how or "linear"
    shade: dict = dict(cmap=cmap, how=how, vmin=vmin, vmax=vmax, color_key=color_key)
    if color_key is not None:
        return shade
    if _shade._is_categorical(df[name]._meta):
        raise TypeError(
            f"color: column {name!r} holds categories; on Dask give color_key={{category: "
            "colour}} (the default colours follow the order of first appearance)"
        )
    if how == "eq_hist":
        raise TypeError(
            'how="eq_hist" of a column\'s values is not drawn on Dask (it needs every value); '
            'give how="linear" or "log" with vmin and vmax'
        )
    if vmin is None or vmax is None:
        import dask

        bounds = (df[name].min(), df[name].max())
        if client is None:
            lo, hi = dask.compute(*bounds)
        else:
            lo, hi = client.gather(client.compute(list(bounds)))
        shade["vmin"] = float(lo) if vmin is None else vmin
        shade["vmax"] = float(hi) if vmax is None else vmax
    return shade


def _named(p: int, error: Exception) -> Exception:
    """``error`` with the partition it came from."""
    return type(error)(f"partition {p}: {error}")


def _threads() -> Optional[int]:
    """The number of threads of the ``dask.distributed`` worker running this task, or None
    outside one. A task draws on that many threads: rayon's global pool has one a core, and
    worker processes of one thread each, one a core, would otherwise run that many threads
    each, competing for the same cores."""
    try:
        from distributed import get_worker

        return int(get_worker().state.nthreads)
    except Exception:  # not in a worker (the local scheduler), or an older distributed
        return None


def _partial(part: Any, p: int, columns: dict, constants: dict, plot: Plot) -> numpy.ndarray:
    cols = _columns(part, p, columns, constants)
    try:
        image = _native._partial(plot, cols, threads=_threads())
    except (ValueError, TypeError) as e:
        raise _named(p, e) from None
    return numpy.asarray(image)


def _count(
    part: Any, p: int, columns: dict, constants: dict, plot: Plot,
    out: Optional[numpy.ndarray] = None,
) -> Optional[numpy.ndarray]:
    """The counts of partition ``p``, or with ``out`` added to it."""
    cols = _columns(part, p, columns, constants)
    try:
        counts = _native._counts(plot, cols, out=out, threads=_threads())
    except (ValueError, TypeError) as e:
        raise _named(p, e) from None
    return counts


def _count_held(
    columns: dict, constants: dict, plot: Plot, indices: Sequence[int], *parts: Any
) -> numpy.ndarray:
    """The counts of ``parts`` (partitions ``indices``, in a worker's memory), added: each
    partition is counted into the same array."""
    out = numpy.zeros((plot.height, plot.width), numpy.uint8)
    for p, part in zip(indices, parts):
        _count(part, p, columns, constants, plot, out=out)
    return out


def _partial_held(
    columns: dict, constants: dict, plot: Plot, indices: Sequence[int], *parts: Any
) -> Optional[numpy.ndarray]:
    """The partial images of ``parts`` (partitions ``indices``, in a worker's memory),
    combined with the blend's operator."""
    out = None
    for p, part in zip(indices, parts):
        image = _partial(part, p, columns, constants, plot)
        if out is None:
            out = image
        else:
            _native._combine(out, image, plot)
    return out


def _add_counts(counts: Sequence[numpy.ndarray]) -> numpy.ndarray:
    out = numpy.array(counts[0])
    for c in counts[1:]:
        _native._add_counts(out, c)
    return out


def _combine(images: Sequence[numpy.ndarray], plot: Plot) -> numpy.ndarray:
    out = numpy.array(images[0])
    for image in images[1:]:
        _native._combine(out, image, plot)
    return out


def _finish(image: numpy.ndarray, plot: Plot) -> numpy.ndarray:
    out = numpy.array(image)
    _native._finish(out, plot)
    return out


def _bin(
    part: Any, p: int, columns: dict, constants: dict, plot: Plot, tile: Tuple[int, int]
) -> tuple:
    cols = _columns(part, p, columns, constants)
    try:
        bins = _native._bin(plot, cols, p << 40, *tile)
    except (ValueError, TypeError) as e:
        raise _named(p, e) from None
    return tuple(bins)


def _tile(pieces: list, rect: Sequence[int], layout: dict, plot: Plot) -> numpy.ndarray:
    """Draws one tile from the pieces every partition sent it, in index order."""
    vertices = numpy.concatenate([v for v, _ in pieces])
    index = numpy.concatenate([i for _, i in pieces])
    if index.size > 1 and not numpy.all(index[1:] > index[:-1]):
        vertices = vertices[numpy.argsort(index, kind="stable")]
    x0, y0, x1, y1 = rect
    image = _native._render_tile(plot, vertices, (x0, y0, x1, y1), **layout)
    return numpy.asarray(image)


def _assemble(
    tiles: Sequence[numpy.ndarray], rects: Sequence[Sequence[int]], width: int, height: int
) -> numpy.ndarray:
    out = numpy.empty((height, width, 4), numpy.uint8)
    for tile, (x0, y0, x1, y1) in zip(tiles, rects):
        out[y0:y1, x0:x1] = tile
    return out
