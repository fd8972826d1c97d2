"""Type stubs of pointillist.Image."""

import os
from typing import Any, Optional, Union

import numpy

class Image(numpy.ndarray[Any, numpy.dtype[numpy.uint8]]):
    """An (height, width, 4) uint8 RGBA ndarray that Jupyter shows as a picture."""

    def save(self, path: Union[str, os.PathLike[str]]) -> None:
        """Write the image as an RGBA8 PNG, atomically."""
    def _repr_png_(self) -> Optional[bytes]: ...
