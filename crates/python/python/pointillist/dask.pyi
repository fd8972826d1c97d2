"""Type stubs of pointillist.dask."""

from typing import Any, Literal, Optional, Tuple, Union

import numpy
import numpy.typing as npt

from ._image import Image

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
    blend: Literal["add", "alpha", "max", "replace"] = "add",
    x_range: Optional[Tuple[float, float]] = None,
    y_range: Optional[Tuple[float, float]] = None,
    clear: int = 0xFF000000,
    texture: Optional[npt.NDArray[numpy.uint8]] = None,
    tile_size: Union[int, Tuple[int, int]] = 256,
    split_every: int = 8,
    client: Any = None,
) -> Image:
    """The rows of a Dask DataFrame drawn on a dask.distributed cluster, exactly as
    pointillist.points draws them in order (a persisted df: one task a worker, no graph)."""
