"""Colour from values: colormaps (matplotlib's by name when it is installed, a few built in),
the normalisations datashader names (``how="linear" | "log" | "eq_hist"``), categorical
colour keys, and the shading of a counted draw's counts (datashader's ``tf.shade``)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, Optional, Union

import numpy
import numpy.typing as npt

#: Entries of every colormap's lookup table: a value's colour is entry
#: ``min(255, floor(t * 256))`` of its normalised value ``t`` in 0..1, as matplotlib looks up
#: a ``Colormap`` of 256 entries.
N = 256

#: Colormaps built in, as stops spread evenly from 0 to 1 and interpolated linearly in RGB.
#: "viridis" is matplotlib's sampled at 17 stops (within 5 levels of matplotlib's table, which
#: is used when matplotlib is installed); "fire" follows colorcet's (black, red, orange,
#: yellow, white).
BUILTIN: dict[str, list[str]] = {
    "viridis": ["#440154", "#47186A", "#472C7B", "#424085", "#3A528B", "#32628D", "#2C728E",
                "#26818E", "#20908C", "#1E9F88", "#28AE7F", "#3EBC73", "#5EC961", "#83D34B",
                "#ADDC30", "#D7E219", "#FDE724"],
    "fire": ["#000000", "#5B0B00", "#A11C00", "#E03800", "#FF6A00", "#FF9D00", "#FFCC1A",
             "#FFF27A", "#FFFFFF"],
    "gray": ["#000000", "#FFFFFF"],
    "blues": ["#F7FBFF", "#08306B"],
}

#: The categorical colours used when a category column has no ``color_key``: matplotlib's
#: "tab10".
CATEGORIES = ["#1F77B4", "#FF7F0E", "#2CA02C", "#D62728", "#9467BD", "#8C564B", "#E377C2",
              "#7F7F7F", "#BCBD22", "#17BECF"]

HOWS = ("linear", "log", "eq_hist")

Cmap = Union[str, Sequence[Any], None]


def _matplotlib() -> Any:
    """matplotlib (with ``matplotlib.colors``), or None when it is not installed."""
    try:
        import matplotlib
        import matplotlib.colors
    except ImportError:
        return None
    return matplotlib


def _rgba(color: Any, what: str) -> tuple[float, float, float, float]:
    """One colour as RGBA floats in 0..1: ``"#RRGGBB"``, ``"#RRGGBBAA"``, an ``(r, g, b)`` or
    ``(r, g, b, a)`` of floats in 0..1, or (with matplotlib installed) any colour matplotlib
    names."""
    if isinstance(color, str) and color.startswith("#") and len(color) in (7, 9):
        try:
            parts = [int(color[i:i + 2], 16) / 255 for i in range(1, len(color), 2)]
        except ValueError:
            parts = []
        if parts:
            return (parts[0], parts[1], parts[2], parts[3] if len(parts) == 4 else 1.0)
    if isinstance(color, (tuple, list)) and len(color) in (3, 4):
        values = [float(c) for c in color]
        if all(0.0 <= c <= 1.0 for c in values):
            return (values[0], values[1], values[2], values[3] if len(values) == 4 else 1.0)
    matplotlib = _matplotlib()
    if matplotlib is not None and isinstance(color, str):
        try:
            r, g, b, a = matplotlib.colors.to_rgba(color)
            return (r, g, b, a)
        except ValueError:
            pass
    raise ValueError(
        f"{what}: {color!r} is not a colour ('#RRGGBB', '#RRGGBBAA', (r, g, b[, a]) in 0..1"
        + (", or a matplotlib colour name" if matplotlib is not None else "")
        + ")"
    )


def _stops(colors: Sequence[Any], what: str) -> npt.NDArray[numpy.uint8]:
    """The lookup table of colours ``colors`` spread evenly from 0 to 1, interpolated
    linearly in RGB(A): ``(N, 4)`` RGBA bytes."""
    if len(colors) == 0:
        raise ValueError(f"{what} is an empty list of colours")
    stops = numpy.array([_rgba(c, what) for c in colors], dtype=numpy.float64)
    if len(stops) == 1:
        stops = numpy.vstack([stops, stops])
    at = numpy.linspace(0.0, 1.0, len(stops))
    t = numpy.linspace(0.0, 1.0, N)
    table = numpy.stack([numpy.interp(t, at, stops[:, c]) for c in range(4)], axis=1)
    return numpy.asarray(numpy.round(table * 255), dtype=numpy.uint8)


def colormap(cmap: Cmap) -> npt.NDArray[numpy.uint8]:
    """The ``(256, 4)`` RGBA lookup table of ``cmap``: a name (matplotlib's colormaps when
    matplotlib is installed, else :data:`BUILTIN`), a list of colours, or None ("viridis")."""
    if cmap is None:
        cmap = "viridis"
    if isinstance(cmap, str):
        matplotlib = _matplotlib()
        if matplotlib is not None and cmap in matplotlib.colormaps:
            lut = matplotlib.colormaps[cmap].resampled(N)(numpy.arange(N), bytes=True)
            return numpy.asarray(lut, dtype=numpy.uint8)
        if cmap in BUILTIN:
            return _stops(BUILTIN[cmap], "cmap")
        where = "matplotlib's colormaps or " if matplotlib is not None else ""
        raise ValueError(
            f"cmap: unknown colormap {cmap!r} (expected one of {where}the built-in "
            f"{', '.join(BUILTIN)}, or a list of colours)"
        )
    if hasattr(cmap, "resampled") and callable(cmap):  # a matplotlib Colormap
        return numpy.asarray(cmap.resampled(N)(numpy.arange(N), bytes=True), dtype=numpy.uint8)
    if isinstance(cmap, Sequence):
        return _stops(cmap, "cmap")
    raise TypeError(
        f"cmap must be a colormap's name or a list of colours; got {type(cmap).__name__}"
    )


def _argb(rgba: npt.NDArray[numpy.uint8]) -> npt.NDArray[numpy.uint32]:
    """``(n, 4)`` RGBA bytes as D3DCOLORs 0xAARRGGBB."""
    c = rgba.astype(numpy.uint32)
    return numpy.asarray(
        (c[:, 3] << 24) | (c[:, 0] << 16) | (c[:, 1] << 8) | c[:, 2], dtype=numpy.uint32
    )


def normalise(
    values: npt.NDArray[numpy.float64],
    how: Optional[str],
    vmin: Optional[float],
    vmax: Optional[float],
) -> npt.NDArray[numpy.float64]:
    """``values`` mapped to 0..1 as ``how`` says, between ``vmin`` and ``vmax`` (by default the
    values' least and greatest): "linear" ``(v - vmin) / (vmax - vmin)``, "log" the same of
    ``log10`` (values must be positive), "eq_hist" the fraction of the values (clipped to
    ``vmin..vmax``) at or below each, rescaled so that the least is 0 and the greatest 1
    (histogram equalisation: every colour of the map shows as many values). Values outside
    ``vmin..vmax`` are clipped; equal ``vmin`` and ``vmax`` map everything to 0."""
    if not isinstance(how, str) or how not in HOWS:
        raise ValueError(f"how: unknown normalisation {how!r} (expected one of: "
                         f"{', '.join(HOWS)})")
    if values.size == 0:
        return values
    lo = float(numpy.min(values)) if vmin is None else float(vmin)
    hi = float(numpy.max(values)) if vmax is None else float(vmax)
    if not (numpy.isfinite(lo) and numpy.isfinite(hi)) or lo > hi:
        raise ValueError(f"vmin {lo!r} and vmax {hi!r} must be finite, vmin <= vmax")
    v = numpy.clip(values, lo, hi)
    if how == "log":
        if lo <= 0:
            raise ValueError(f'how="log" needs positive values; vmin is {lo!r}')
        v, lo, hi = numpy.log10(v), numpy.log10(lo), numpy.log10(hi)
    if how == "eq_hist":
        unique, inverse, counts = numpy.unique(v, return_inverse=True, return_counts=True)
        cdf = numpy.cumsum(counts, dtype=numpy.float64)
        if len(cdf) == 1:
            return numpy.zeros(v.shape)
        cdf = (cdf - cdf[0]) / (cdf[-1] - cdf[0])
        return numpy.asarray(cdf[inverse.reshape(v.shape)], dtype=numpy.float64)
    if hi == lo:
        return numpy.zeros(v.shape)
    return numpy.asarray((v - lo) / (hi - lo), dtype=numpy.float64)


def lookup(t: npt.NDArray[numpy.float64], lut: npt.NDArray[Any]) -> Any:
    """Entries of ``lut`` (its rows: RGBA bytes, or D3DCOLORs) for normalised values ``t`` in
    0..1."""
    index = numpy.minimum((t * N).astype(numpy.int64), N - 1)
    return lut[index]


def _is_categorical(values: Any) -> bool:
    """Whether a column holds categories (strings, objects, booleans, a pandas categorical)
    rather than numbers."""
    dtype = getattr(values, "dtype", None)
    if dtype is None:
        dtype = numpy.asarray(values).dtype
    return getattr(dtype, "kind", "O") in "OUSb" or str(dtype) == "category"


def _first_appearance(values: Any) -> tuple[npt.NDArray[numpy.int64], list[Any]]:
    """Each value's category number and the categories, numbered in the order of their first
    appearance: pandas' hashing (``factorize``) where pandas is installed, numpy's sorting for
    numbers, booleans and numpy strings otherwise, one pass in Python for the rest and for
    missing values (which are categories of their own)."""
    array = numpy.asarray(values)
    codes: Any = None
    labels: Any = None
    try:
        import pandas
    except ImportError:
        if array.ndim == 1 and array.dtype.kind in "biuUS":
            labels, codes = numpy.unique(array, return_inverse=True)
            used, first, inverse = numpy.unique(codes, return_index=True, return_inverse=True)
            order = numpy.argsort(first, kind="stable")
            rank = numpy.empty(len(order), dtype=numpy.int64)
            rank[order] = numpy.arange(len(order))
            codes, labels = rank[inverse.reshape(-1)], labels[used[order]]
    else:
        cat = getattr(values, "cat", values)
        if isinstance(getattr(cat, "categories", None), pandas.Index):
            codes, picks = pandas.factorize(numpy.asarray(cat.codes), sort=False)
            labels = [cat.categories[i] if i >= 0 else None for i in picks]
        elif array.ndim == 1:
            codes, labels = pandas.factorize(array, sort=False)
    if codes is None or (numpy.asarray(codes) < 0).any() or any(
        isinstance(c, float) and c != c for c in labels
    ):
        array = numpy.asarray(values, dtype=object)
        categories = list(dict.fromkeys(array.tolist()))
        index = {c: i for i, c in enumerate(categories)}
        found = numpy.fromiter((index[c] for c in array.tolist()), dtype=numpy.int64,
                               count=len(array))
        return found, categories
    return numpy.asarray(codes, dtype=numpy.int64), [_plain(c) for c in labels]


def _plain(label: Any) -> Any:
    """A numpy scalar as the Python value it holds (the key a ``color_key`` uses)."""
    return label.item() if isinstance(label, numpy.generic) else label


def colors_of(
    arg: str,
    values: Any,
    cmap: Cmap,
    how: Optional[str],
    vmin: Optional[float],
    vmax: Optional[float],
    color_key: Optional[Mapping[Any, Any]],
) -> npt.NDArray[numpy.uint32]:
    """The D3DCOLOR of each value of the column ``values``: a category's colour from
    ``color_key`` (strings, categoricals, booleans, or any column with a ``color_key``), a
    number's from the colormap after :func:`normalise` (``how`` "linear" by default)."""
    if color_key is not None or _is_categorical(values):
        codes, categories = _first_appearance(values)
        if color_key is None and cmap is not None:
            lut = colormap(cmap)
            picks = numpy.round(numpy.linspace(0, N - 1, len(categories))).astype(numpy.int64)
            color_key = {c: tuple(lut[i] / 255) for c, i in zip(categories, picks)}
        if color_key is None:
            if len(categories) > len(CATEGORIES):
                raise ValueError(
                    f"{arg} has {len(categories)} categories, more than the "
                    f"{len(CATEGORIES)} default colours; give color_key={{category: colour}}"
                )
            color_key = dict(zip(categories, CATEGORIES))
        if not isinstance(color_key, Mapping):
            raise TypeError(f"color_key must be a dict of categories to colours; got "
                            f"{type(color_key).__name__}")
        missing = [c for c in categories if c not in color_key]
        if missing:
            raise ValueError(f"color_key has no colour for the category {missing[0]!r} of "
                             f"{arg}")
        rgba = numpy.array([[round(v * 255) for v in _rgba(color_key[c], "color_key")]
                            for c in categories], dtype=numpy.uint8)
        return _argb(rgba)[codes]
    numbers = numpy.asarray(values, dtype=numpy.float64)
    if numbers.ndim != 1:
        raise ValueError(f"{arg} must be a 1-D column of values; got shape {numbers.shape}")
    nan = numpy.isnan(numbers)
    if nan.any():
        raise ValueError(f"{arg}[{int(numpy.argmax(nan))}] is NaN")
    # The map's 256 D3DCOLORs, gathered once a point (not four bytes a point, then packed).
    return lookup(normalise(numbers, how or "linear", vmin, vmax), _argb(colormap(cmap)))


def shade_counts(
    counts: npt.NDArray[numpy.uint8],
    clear: int,
    cmap: Cmap,
    how: Optional[str],
    vmin: Optional[float],
    vmax: Optional[float],
) -> npt.NDArray[numpy.uint8]:
    """The ``(h, w, 4)`` RGBA image of per-pixel point counts (saturated at 255), datashader's
    ``tf.shade``: a pixel no point covers shows ``clear``; every other pixel the colormap's
    colour of its count, normalised over the covered pixels' counts (``how`` "eq_hist" by
    default, as datashader's)."""
    h, w = counts.shape
    clear_rgba = numpy.array(
        [(clear >> 16) & 0xFF, (clear >> 8) & 0xFF, clear & 0xFF, (clear >> 24) & 0xFF],
        dtype=numpy.uint8,
    )
    out = numpy.empty((h, w, 4), dtype=numpy.uint8)
    out[...] = clear_rgba
    covered = counts > 0
    if covered.any():
        t = normalise(counts[covered].astype(numpy.float64), how or "eq_hist", vmin, vmax)
        out[covered] = lookup(t, colormap(cmap))
    return out
