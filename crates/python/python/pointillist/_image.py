"""The array pointillist returns: a numpy array that shows itself as a picture in Jupyter."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, Optional, Tuple, Union

import numpy

if TYPE_CHECKING:
    import PIL.Image
    from matplotlib.axes import Axes
    from matplotlib.image import AxesImage

    from ._native import Plot

Range = Optional[Tuple[float, float]]

if TYPE_CHECKING:
    _Array = numpy.ndarray[Any, numpy.dtype[numpy.uint8]]
else:  # numpy 1.21 arrays take no subscript at run time
    _Array = numpy.ndarray


class Image(_Array):
    """An ``(height, width, 4)`` uint8 RGBA numpy array (rows top to bottom) that Jupyter and
    IPython display as a PNG. It is an ordinary ``numpy.ndarray`` in every other respect: views,
    slices and arithmetic work as usual (``numpy.asarray(img)`` gives the plain array without
    copying).

    An image drawn by :func:`pointillist.points` or :func:`pointillist.dask.points` knows the
    data it shows: ``x_range`` and ``y_range`` (the ranges it was drawn with, or None for pixel
    coordinates), ``extent`` for ``ax.imshow(img, extent=img.extent, origin="upper")``, and
    ``x_name``/``y_name`` (the columns' names, where they had one). A copy, or a view of the
    whole image, keeps them; a slice of another size does not (its ranges are unknown), and
    its ``extent`` is that of its own pixels."""

    x_range: Range = None
    y_range: Range = None
    x_name: Optional[str] = None
    y_name: Optional[str] = None

    def __array_finalize__(self, obj: Any) -> None:
        # Only an array of the same height and width shows the same data.
        if obj is None or getattr(obj, "shape", ())[:2] != self.shape[:2]:
            return
        for name in ("x_range", "y_range", "x_name", "y_name"):
            value = getattr(obj, name, None)
            if value is not None:
                setattr(self, name, value)

    def _located(
        self, plot: Plot, x_name: Optional[str] = None, y_name: Optional[str] = None
    ) -> Image:
        """This image with the data ranges of ``plot`` (which drew it) and the columns'
        names."""
        self.x_range, self.y_range = plot.x_range, plot.y_range
        self.x_name, self.y_name = x_name, y_name
        return self

    @property
    def extent(self) -> Tuple[float, float, float, float]:
        """``(left, right, bottom, top)`` for matplotlib's ``imshow(img, extent=img.extent,
        origin="upper")``: the data ranges, ``(x_lo, x_hi, y_lo, y_hi)``, which span the image
        edge to edge (the one formula, docs/PYTHON.md). Along an axis drawn in pixel
        coordinates, the pixels' edges: ``(-0.5, width - 0.5)`` across and
        ``(height - 0.5, -0.5)`` up (y downwards), matplotlib's own default."""
        height, width = self.shape[:2]
        x = self.x_range if self.x_range is not None else (-0.5, width - 0.5)
        y = self.y_range if self.y_range is not None else (height - 0.5, -0.5)
        return (float(x[0]), float(x[1]), float(y[0]), float(y[1]))

    def to_pil(self) -> PIL.Image.Image:
        """The image as a Pillow ``Image`` in mode RGBA (its own copy of the bytes); Pillow
        must be installed."""
        import PIL.Image

        if self.ndim != 3 or self.shape[2] != 4 or self.dtype != numpy.uint8:
            raise ValueError(
                f"to_pil needs an (h, w, 4) uint8 image; this array has shape {self.shape} "
                f"and dtype {self.dtype}"
            )
        return PIL.Image.fromarray(numpy.array(self.view(numpy.ndarray), order="C"))

    def imshow(
        self,
        ax: Optional[Axes] = None,
        *,
        xlabel: Optional[str] = None,
        ylabel: Optional[str] = None,
        **kwargs: Any,
    ) -> AxesImage:
        """Draw the image on matplotlib Axes ``ax`` (by default ``pyplot.gca()``) at its
        ``extent``, each pixel one image pixel (``interpolation="nearest"``), with the axes
        labelled ``xlabel`` and ``ylabel`` (by default the columns' names, else "x" and "y")
        and, when it has data ranges, ``aspect="auto"`` (the axes' shape, as ``scatter``);
        other keywords go to ``ax.imshow``. Returns the ``AxesImage``. matplotlib is needed
        only for this method."""
        if ax is None:
            import matplotlib.pyplot as plt

            ax = plt.gca()
        options: dict[str, Any] = dict(origin="upper", interpolation="nearest")
        if self.x_range is not None or self.y_range is not None:
            options["aspect"] = "auto"
        options.update(kwargs)
        shown = ax.imshow(self.view(numpy.ndarray), extent=self.extent, **options)
        ax.set_xlabel(xlabel if xlabel is not None else self.x_name or "x")
        ax.set_ylabel(ylabel if ylabel is not None else self.y_name or "y")
        return shown

    def save(self, path: Union[str, os.PathLike[str]]) -> None:
        """Write the image to ``path`` as an RGBA8 PNG holding its exact bytes, alpha
        included, as ``pointillist render`` writes its output: the file appears complete or not
        at all (an existing file is left untouched on error)."""
        from . import _native

        _native._save_png(str(path), numpy.ascontiguousarray(self).view(numpy.ndarray))

    def _repr_png_(self) -> Optional[bytes]:
        """The PNG bytes of the image, or ``None`` when the array is no longer an
        ``(h, w, 4)`` uint8 image (a slice of one channel, say) so that the usual text
        representation is shown instead."""
        from . import _native

        if self.ndim != 3 or self.shape[2] != 4 or self.dtype != numpy.uint8 or self.size == 0:
            return None
        return _native._encode_png(numpy.ascontiguousarray(self).view(numpy.ndarray))
