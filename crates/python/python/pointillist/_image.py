"""The array pointillist returns: a numpy array that shows itself as a picture in Jupyter."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, Optional, Union

import numpy


if TYPE_CHECKING:
    _Array = numpy.ndarray[Any, numpy.dtype[numpy.uint8]]
else:  # numpy 1.21 arrays take no subscript at run time
    _Array = numpy.ndarray


class Image(_Array):
    """An ``(height, width, 4)`` uint8 RGBA numpy array (rows top to bottom) that Jupyter and
    IPython display as a PNG. It is an ordinary ``numpy.ndarray`` in every other respect: views,
    slices and arithmetic work as usual (``numpy.asarray(img)`` gives the plain array without
    copying)."""

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
