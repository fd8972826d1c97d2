"""Exact Direct3D 9 point sprites from numpy.

pointillist draws points the way a Direct3D 9 device draws a point list, pixel for pixel, on
the CPU (or the GPU), with no Direct3D and no display:

- :func:`points` draws millions of sized, coloured, blended points from numpy arrays in one
  call and returns the image as an ``(height, width, 4)`` uint8 RGBA array;
- :class:`Device` is the D3D9 device itself (render states, texture stages, samplers,
  transforms, viewport, clip planes, ``draw_points``);
- :func:`render_scene` and :func:`animate` draw scene files (docs/spec/SCENE.md) as the
  ``pointillist`` command line does;
- :mod:`pointillist.dask` draws a Dask DataFrame on a cluster, bit for bit as :func:`points`
  draws all its rows at once;
- :func:`behaviours` lists the device behaviour switches (where real D3D9 devices differ),
  which every one of them takes as ``behaviour={"minimum_size": "one_pixel", ...}``.

Example::

    import numpy as np, pointillist
    rng = np.random.default_rng(0)
    x, y = rng.normal(size=(2, 1_000_000)).astype(np.float32)
    img = pointillist.points(x, y, width=800, height=600, color=0xFF102040,
                             x_range=(-4, 4), y_range=(-3, 3))

Errors raise ``ValueError``/``TypeError`` (bad arguments: dtypes, shapes, NaNs, lengths),
:class:`Error` (a call the device refuses) or :class:`SceneError` (a scene file), each with
the one-line message the command line prints.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, Optional, Tuple, Union

import numpy
import numpy.typing as npt

from . import _native, _shade
from ._image import Image
from ._native import Device, Error, Plot, SceneError, lanes

if TYPE_CHECKING:
    from ._native import _Backend as Backend
    from ._native import _Behaviour as Behaviour
    from ._native import _Blend as Blend
    from ._native import _Marker as Marker
    from ._native import _SizeUnits as SizeUnits

#: A column argument: anything numpy turns into a 1-D array of numbers.
Column = npt.ArrayLike

__all__ = [
    "Device",
    "Error",
    "Image",
    "Plot",
    "SceneError",
    "animate",
    "behaviour_profiles",
    "behaviours",
    "lanes",
    "points",
    "render_scene",
]


def points(
    data: Any = None,
    x: Union[str, Column, None] = None,
    y: Union[str, Column, None] = None,
    *,
    size: Union[float, str, Column] = 1.0,
    color: Union[int, str, Column] = 0xFFFFFFFF,
    z: Union[str, Column, None] = None,
    width: int,
    height: int,
    blend: Blend = "add",
    x_range: Optional[Tuple[float, float]] = None,
    y_range: Optional[Tuple[float, float]] = None,
    clear: int = 0xFF000000,
    texture: Optional[npt.NDArray[numpy.uint8]] = None,
    backend: Backend = "cpu",
    behaviour: Behaviour = None,
    cmap: _shade.Cmap = None,
    how: Optional[str] = None,
    vmin: Optional[float] = None,
    vmax: Optional[float] = None,
    color_key: Optional[Mapping[Any, Any]] = None,
    marker: Marker = "square",
    size_units: SizeUnits = "pixels",
) -> Image:
    """Draw one point sprite per row of ``x, y`` and return the image.

    Each point is a pre-transformed Direct3D 9 vertex (D3DFVF_XYZRHW) drawn as a square of
    side ``size`` pixels centred on its position (docs/spec/SPEC.md 4.1: pixel ``(i, j)`` is
    covered when ``X - S/2 <= i < X + S/2`` and likewise for ``j``), in row order, onto a
    ``width`` x ``height`` target cleared to ``clear``. The result is the same, bit for bit,
    as the same vertices and render states drawn from a scene file by ``pointillist render``.

    It is called with arrays, ``points(x, y, ...)``, or with a table and the names of its
    columns, ``points(data, x="col", y="col", size=..., color=..., z=...)``: ``data`` a pandas
    DataFrame, a dict of 1-D arrays or an Arrow table (anything with ``__arrow_c_stream__`` or
    ``__arrow_c_array__``: a pyarrow Table, RecordBatch or RecordBatchReader, a polars
    DataFrame, a DuckDB result), and any of ``size``, ``color`` and ``z`` a column name (a
    string) or, as with arrays, a constant or an array (with an Arrow table, a constant only).
    Columns of numpy dtypes, and Arrow float32, float64 and uint32 columns, are read in place;
    an Arrow table's record batches are drawn one after another, in order. A null raises
    ``ValueError`` naming the column and the first null row (positions, sizes, colours and
    depths alike: a NaN size or depth is refused the same way).

    Parameters
    ----------
    data : pandas.DataFrame, dict of arrays, Arrow table, or None
        The table whose columns ``x``, ``y`` (and ``size``, ``color``, ``z`` where they are
        strings) name.
    x, y : 1-D arrays of real numbers, or column names
        Positions. With ``x_range``/``y_range``, data coordinates mapped by
        ``X = (x - x_lo) * (width / (x_hi - x_lo)) - 0.5`` and
        ``Y = (y_hi - y) * (height / (y_hi - y_lo)) - 0.5`` (y upwards; computed in float64,
        rounded once to float32); without them, pixel coordinates (pixel centres at integers,
        y downwards). C-contiguous float32 and float64 arrays are read in place, without a
        copy; other dtypes are converted once.
    size : float, 1-D array or column name, default 1.0
        Side of each square (diameter of each circle) in pixels, exact (not rounded; a square
        covering no pixel centre draws nothing), clamped to 0..8192; in x's data units with
        ``size_units="data"``. matplotlib's ``scatter(s=...)`` is an area in points squared:
        ``size = sqrt(s) * dpi / 72`` pixels draws the same side (docs/PYTHON.md, "Markers
        and sizes").
    color : int, 1-D uint32 array, (n, 4) uint8 array or column name, default 0xFFFFFFFF
        D3DCOLORs 0xAARRGGBB, or RGBA bytes per point; read in place.
    z : 1-D array, column name or None
        Depths in 0..1 for the depth test (LESSEQUAL, depth written): the nearest point wins
        whatever the order. Points outside 0..1 are clipped, as Direct3D clips them.
    width, height : int
        The target's size in pixels (1..16384).
    blend : {"add", "alpha", "max", "replace"}
        "add": ONE/ONE, channels add and saturate; "alpha": SRCALPHA/INVSRCALPHA; "max":
        BLENDOP MAX; "replace": no blending, the last point wins.
    x_range, y_range : (lo, hi) or None
        The data interval the target shows along each axis.
    clear : int, default 0xFF000000
        The D3DCOLOR the target starts as (opaque black).
    texture : (h, w, 4) uint8 array or None
        An RGBA texture every point shows as a point sprite (POINTSPRITEENABLE), multiplied by
        the point's colour and alpha, filtered linearly, clamped at its edges.
    backend : {"cpu", "gpu"}
        "cpu" is the reference; "gpu" draws with wgpu where the build has it.
    behaviour : dict or None
        Device behaviour switches, ``{name: option}`` (:func:`behaviours` lists them; the
        defaults otherwise). ``{"minimum_size": "one_pixel"}`` draws sizes below 1 as 1.
    cmap, how, vmin, vmax, color_key
        Colour from values (any of them given turns it on). With ``color`` a column (or array)
        of numbers: each point's colour is ``cmap``'s (a matplotlib colormap's name when
        matplotlib is installed, a built-in one's, "viridis", "fire", "gray" or "blues", or a
        list of colours; "viridis" by default) at its value normalised between ``vmin`` and
        ``vmax`` (the values' least and greatest by default) as ``how`` says: "linear" (the
        default), "log" or "eq_hist" (histogram equalisation). With a column of categories
        (strings, categoricals, or any column with ``color_key``): ``color_key[category]``
        (matplotlib's "tab10" colours, or ``cmap``'s spread evenly, by default). With one
        ``color`` (a constant) and a draw that is counted ("add", "max" or "replace", no
        ``z``, no texture): the counts of points on each pixel (saturating at 255) shaded
        with ``cmap`` as datashader's ``tf.shade`` does (``how`` "eq_hist" by default), the
        pixels no point covers left ``clear``.

    marker : {"square", "circle"}, default "square"
        "square": the D3D9 point. "circle": the same square drawn as a point sprite showing an
        antialiased disc (a 64x64 texture and its mip chain, sampled trilinearly, multiplied
        by the point's colour); with "alpha" the disc's coverage is the alpha, with "add" and
        "max" it scales the colour, with "replace" the alpha test keeps the texels at least
        half covered. Not with ``texture``, and never counted (so not shaded by counts).
    size_units : {"pixels", "data"}, default "pixels"
        "data": ``size`` in units of x's data range, ``pixels = size * width / (x_hi -
        x_lo)`` (the scale of the formula that maps x, in float64, rounded once to float32);
        needs ``x_range`` and ``y_range``. With unequal scales a point stays round or square
        on the screen, its side measured along x.

    Returns
    -------
    Image
        An ``(height, width, 4)`` uint8 RGBA array (a ``numpy.ndarray`` subclass that shows
        itself as a picture in Jupyter), rows top to bottom, that knows its ``x_range``,
        ``y_range`` and ``extent`` (``img.imshow(ax)`` draws it on matplotlib Axes at its data
        coordinates; ``img.to_pil()`` makes a Pillow image).

    Raises
    ------
    ValueError, TypeError
        For mismatched lengths, NaN positions, depths or sizes (naming the first row), arrays
        of the wrong dimension or dtype, bad ranges, unknown blends, unknown behaviour
        switches or options.
    pointillist.Error
        When the device refuses the target (its size).

    The arguments that describe the plot rather than the points (``width`` to ``behaviour``)
    are checked first, together, as one :class:`Plot`.

    The GIL is released while the points are drawn.
    """
    arrow = _is_arrow(data) and any(isinstance(v, str) for v in (x, y, size, color, z))
    if not arrow:
        x, y, size, color, z, x_name, y_name = _columns(data, x, y, size, color, z)
    plot = Plot(
        width,
        height,
        blend=blend,
        x_range=x_range,
        y_range=y_range,
        clear=clear,
        texture=texture,
        behaviour=behaviour,
        backend=backend,
        marker=marker,
        size_units=size_units,
    )
    shading = any(v is not None for v in (cmap, how, vmin, vmax, color_key))
    shade: dict[str, Any] = dict(cmap=cmap, how=how, vmin=vmin, vmax=vmax)
    constant = isinstance(color, int) or (not isinstance(color, str) and numpy.ndim(color) == 0)
    if arrow:
        x_name, y_name, z_name = _arrow_names(x, y, z)
        if shading and isinstance(color, str):
            data, values = _arrow_values(data, color)
            color = _shade.colors_of("color", values, color_key=color_key, **shade)
        image = _native.points_arrow(plot, data, x_name, y_name, size=_any(size),
                                     color=_any(color), z=z_name, counts=shading and constant)
    else:
        if shading and not constant:
            color = _shade.colors_of("color", color, color_key=color_key, **shade)
        if shading and constant:
            image = _native._counts(plot, _any((x, y, z, size, color)))
            if image is None:
                raise ValueError(_NOT_COUNTED)
        else:
            image = _native.points(plot, _any(x), _any(y), size=size, color=color, z=z)
    if shading and constant:
        image = _shade.shade_counts(image, plot.clear, **shade).view(Image)
    return image._located(plot, x_name, y_name)


_NOT_COUNTED = (
    'only a draw of one colour is shaded from its counts: a constant color, blend "add", '
    '"max" or "replace", no z, no texture'
)


def _arrow_values(data: Any, name: str) -> Tuple[Any, Any]:
    """Column ``name`` of an Arrow table as a numpy array (for colour from values), and the
    table to draw: a polars frame's own column, else pyarrow's (a stream, which can be read
    only once, is read into a pyarrow Table first). A null raises ``ValueError``."""
    if hasattr(data, "get_column"):  # polars
        if name not in data.columns:
            raise ValueError(f"color: column {name!r} is not in data (its columns: "
                             f"{', '.join(data.columns)})")
        column = data.get_column(name)
        values = column.to_numpy()
        nulls = numpy.asarray(column.is_null().to_numpy())
    else:
        try:
            import pyarrow
        except ImportError:
            raise TypeError(
                "colour from an Arrow table's values needs pyarrow (or a polars frame)"
            ) from None
        if not hasattr(data, "column"):
            data = pyarrow.table(data)
        if name not in data.schema.names:
            raise ValueError(f"color: column {name!r} is not in data (its columns: "
                             f"{', '.join(data.schema.names)})")
        column = data.column(name)
        if pyarrow.types.is_dictionary(column.type):
            column = column.cast(column.type.value_type)
        values = column.to_numpy(zero_copy_only=False)
        nulls = numpy.asarray(column.is_null())
    if nulls.any():
        raise ValueError(f"color: column {name!r} is null at row {int(numpy.argmax(nulls))}")
    return data, values


def _any(value: Any) -> Any:
    """``value``, whose type the compiled function checks."""
    return value


def _is_arrow(data: Any) -> bool:
    """Whether ``data`` is read through the Arrow PyCapsule interface: it has
    ``__arrow_c_stream__`` or ``__arrow_c_array__`` and is not a pandas frame (read as the
    numpy arrays it holds) or a dict."""
    if data is None or _is_pandas(data) or isinstance(data, Mapping):
        return False
    kind = type(data)
    return hasattr(kind, "__arrow_c_stream__") or hasattr(kind, "__arrow_c_array__")


def _arrow_names(x: Any, y: Any, z: Any) -> Tuple[str, str, Optional[str]]:
    """With an Arrow table, ``x`` and ``y`` (and ``z`` when given) must name columns."""
    for arg, value in (("x", x), ("y", y), ("z", z)):
        if not isinstance(value, str) and (arg != "z" or value is not None):
            raise TypeError(
                f"{arg} must be a column name with data; got {type(value).__name__}"
            )
    return x, y, z


def _columns(data: Any, x: Any, y: Any, size: Any, color: Any, z: Any) -> tuple:
    """The arrays (or constants) ``x, y, size, color, z`` of a call with arrays or with a
    table and column names, and the names of ``x`` and ``y`` (the columns', a Series')."""
    names = {"x": x, "y": y, "size": size, "color": color, "z": z}
    if not any(isinstance(v, str) for v in names.values()):
        arrays = [a for a in (data, x, y) if a is not None]
        if len(arrays) != 2:
            raise TypeError(
                "points takes the arrays x and y, or data and the names of its x and y columns"
            )
        x, y = arrays
        return x, y, size, color, z, _name(x), _name(y)
    if data is None:
        raise TypeError(f"{_first_name(names)} names a column, but no data was given")
    if not (_is_pandas(data) or isinstance(data, Mapping)):
        raise TypeError(
            "data must be a pandas DataFrame, a dict of arrays or an Arrow table (an object "
            f"with __arrow_c_stream__ or __arrow_c_array__); got {type(data).__name__}"
        )
    for arg in ("x", "y"):
        if not isinstance(names[arg], str):
            raise TypeError(
                f"{arg} must be a column name with data; got {type(names[arg]).__name__}"
            )
    columns = list(data.columns) if _is_pandas(data) else list(data.keys())
    out = {}
    for arg, value in names.items():
        if not isinstance(value, str):
            out[arg] = value
            continue
        if value not in columns:
            raise ValueError(
                f"{arg}: column {value!r} is not in data (its columns: "
                f"{', '.join(map(str, columns))})"
            )
        out[arg] = _column(arg, value, data[value])
    return out["x"], out["y"], out["size"], out["color"], out["z"], x, y


def _first_name(names: dict) -> str:
    arg = next(k for k, v in names.items() if isinstance(v, str))
    return f"{arg}={names[arg]!r}"


def _is_pandas(data: Any) -> bool:
    return type(data).__module__.split(".")[0] == "pandas" and hasattr(data, "columns")


def _column(arg: str, name: str, column: Any) -> Any:
    """Column ``name`` of the table as an array: a numpy-backed column as the array it holds
    (no copy); a nullable (extension) column converted once, refused when it holds a null."""
    if type(column).__module__.split(".")[0] != "pandas":
        return column  # a dict's array: read as an array argument is
    array = column.array if hasattr(column, "array") else column
    if isinstance(getattr(column, "dtype", None), numpy.dtype):
        return column.to_numpy()
    nulls = numpy.asarray(array.isna())
    if nulls.any():
        row = int(numpy.argmax(nulls))
        raise ValueError(f"{arg}: column {name!r} is null at row {row}")
    dtype = getattr(column.dtype, "numpy_dtype", None)
    return column.to_numpy(dtype=dtype)


def _name(column: Any) -> Optional[str]:
    """The name of a column that has one (a pandas Series), for the image's axis labels."""
    name = getattr(column, "name", None)
    return name if isinstance(name, str) else None


render_scene = _native.render_scene


def animate(
    path: Union[str, os.PathLike[str]],
    out: Union[str, os.PathLike[str]],
    *,
    frames: Optional[int] = None,
    backend: Backend = "cpu",
    behaviour: Behaviour = None,
    max_pixels: float = 1e11,
) -> None:
    """Render every frame of a scene's ``[animation]`` to ``out``, as ``pointillist animate``
    does: an animated GIF (``.gif``), an APNG of the exact RGBA bytes (``.png``/``.apng``), a
    numbered PNG sequence (a name with ``%d``, e.g. ``frames/f_%04d.png``) or H.264 through
    ffmpeg (``.mp4``), byte for byte what the command line writes. ``frames`` renders only the
    first ``frames`` frames. ``behaviour`` (a dict such as ``{"minimum_size": "one_pixel"}``)
    sets device behaviour switches over the scene's ``[behaviour]``, as ``--behaviour`` does.
    ``max_pixels`` is the work limit of ``--max-pixels``: a draw that would write more pixels
    (1e11 by default; ``math.inf`` lifts it) is refused before it is drawn.
    The output (every file of a sequence) is written whole or not at all: errors raise
    :class:`SceneError` with the command line's message, and Ctrl-C (``KeyboardInterrupt``,
    checked between the simulation's steps, between frames and between the pieces of a draw)
    leaves nothing behind."""
    return _native.animate(
        str(path),
        str(out),
        frames=frames,
        backend=backend,
        behaviour=behaviour,
        max_pixels=max_pixels,
    )


def behaviours() -> list[dict[str, Any]]:
    """The device behaviour switches: rules on which real D3D9 devices differ, or no record
    decides (docs/spec/SPEC.md, "Device behaviours"), as ``pointillist behaviours --json``
    lists them. A list of dicts, one a switch, with ``name``, ``options`` (their names),
    ``default``, ``evidence`` (the grade of the default's evidence), ``sources``, ``summary``,
    ``rule`` (the SPEC rule) and ``option_effects`` (what each option draws). Set them with
    ``behaviour={name: option}`` on :func:`points`, :class:`Device`, :func:`render_scene`,
    :func:`animate` and :func:`pointillist.dask.points`; ``{"profile": name}`` sets a
    profile's switches first (:func:`behaviour_profiles`)."""
    return _native.behaviours_table()


def behaviour_profiles() -> list[dict[str, Any]]:
    """The behaviour profiles: one name for the options a source shows for a whole device
    (docs/spec/SPEC.md, "Device behaviours"), as ``pointillist behaviours --profiles --json``
    lists them. A list of dicts with ``name``, ``summary``, ``settings`` (a dict of switch
    names to options: the switches the profile sets) and ``sources``. ``behaviour={"profile":
    name, ...}`` sets a profile's switches before the switches beside it."""
    return _native.behaviour_profiles()
