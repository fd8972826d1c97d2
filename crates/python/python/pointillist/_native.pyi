"""Type stubs of ``pointillist._native``, the compiled module (crates/python/src).

The public names are re-exported by ``pointillist``; the functions whose names start with an
underscore are the steps ``pointillist.dask`` runs on its workers. The ``.py`` files of the
package carry their own annotations; this file describes only what is compiled.
"""

import os
from typing import Any, Literal, Optional, Sequence, Tuple, Union

import numpy
import numpy.typing as npt
from typing_extensions import TypeAlias, final

from ._image import Image

__all__ = [
    "Error",
    "SceneError",
    "Device",
    "Plot",
    "points",
    "points_arrow",
    "render_scene",
    "animate",
    "lanes",
    "behaviours_table",
    "behaviour_profiles",
    "_check",
    "_partial",
    "_combine",
    "_counts",
    "_add_counts",
    "_from_counts",
    "_finish",
    "_tiles",
    "_bin",
    "_render_tile",
    "_encode_png",
    "_save_png",
]

# Type aliases of the stubs only (private: the module does not have them at run time).

_Blend: TypeAlias = Literal["add", "alpha", "max", "replace"]
_Backend: TypeAlias = Literal["cpu", "gpu"]
_Marker: TypeAlias = Literal["square", "circle"]
_SizeUnits: TypeAlias = Literal["pixels", "data"]
_Behaviour: TypeAlias = Optional[dict[str, str]]
_Range: TypeAlias = Optional[Tuple[float, float]]
_Column: TypeAlias = npt.ArrayLike
_StateValue: TypeAlias = Union[float, int, bool, str]
_U8Array: TypeAlias = npt.NDArray[numpy.uint8]
_Rect: TypeAlias = Tuple[int, int, int, int]
_Columns: TypeAlias = Tuple[
    _Column, _Column, Optional[_Column], Union[float, _Column], Union[int, _Column]
]
"""The columns of a worker's step: ``(x, y, z, size, color)``; ``size`` and ``color`` may
be constants, ``z`` None."""

class Error(Exception):
    """A call the device refused or a draw that failed; the message is the CLI's one line."""

class SceneError(Error):
    """A scene file that cannot be read or drawn (file, line, column and key)."""

@final
class Plot:
    """The frozen description of a plot: the target, the blend, the data ranges, the clear
    colour, the texture, the behaviour switches and the backend, each checked when it is
    made (``ValueError``/``TypeError`` naming the argument; ``Error`` for a target outside
    1..=16384 per side). Picklable; ``pointillist.dask`` sends it to its workers."""

    def __new__(
        cls,
        width: int,
        height: int,
        blend: _Blend = "add",
        x_range: _Range = None,
        y_range: _Range = None,
        clear: int = 0xFF000000,
        texture: Optional[npt.ArrayLike] = None,
        behaviour: _Behaviour = None,
        backend: _Backend = "cpu",
        marker: _Marker = "square",
        size_units: _SizeUnits = "pixels",
    ) -> "Plot": ...
    @property
    def width(self) -> int:
        """The target's width in pixels."""
    @property
    def height(self) -> int:
        """The target's height in pixels."""
    @property
    def blend(self) -> _Blend:
        """The blend preset's name."""
    @property
    def x_range(self) -> Optional[Tuple[float, float]]:
        """The data interval across the width, or None (x in pixels)."""
    @property
    def y_range(self) -> Optional[Tuple[float, float]]:
        """The data interval up the height, or None (y in pixels, downwards)."""
    @property
    def clear(self) -> int:
        """The D3DCOLOR the target starts as."""
    @property
    def texture(self) -> Optional[_U8Array]:
        """A read-only (h, w, 4) uint8 copy of the texture, or None."""
    @property
    def behaviour(self) -> dict[str, str]:
        """Every behaviour switch's option, by name."""
    @property
    def backend(self) -> _Backend:
        """The backend's name."""
    @property
    def commutes(self) -> bool:
        """Whether the blend's result is independent of the order of the points."""
    @property
    def marker(self) -> _Marker:
        """The marker's name."""
    @property
    def size_units(self) -> _SizeUnits:
        """What sizes are measured in: pixels, or x's data units."""
    def __reduce__(self) -> Tuple[type["Plot"], tuple]: ...

def points(
    plot: Plot,
    x: _Column,
    y: _Column,
    *,
    size: Union[float, _Column],
    color: Union[int, _Column],
    z: Optional[_Column] = None,
) -> Image:
    """One point sprite per row of ``x, y`` drawn as ``plot`` says (``pointillist.points``)."""

def points_arrow(
    plot: Plot,
    data: Any,
    x: str,
    y: str,
    *,
    size: Union[float, str],
    color: Union[int, str, _Column],
    z: Optional[str] = None,
    counts: bool = False,
) -> Any:
    """The rows of an Arrow table (``__arrow_c_stream__`` or ``__arrow_c_array__``), by column
    names, drawn record batch by record batch as ``plot`` says (``pointillist.points``): the
    Image, or with ``counts`` the ``(height, width)`` uint8 counts of a draw of one colour."""

def render_scene(
    path: Union[str, os.PathLike[str]],
    frame: Optional[int] = None,
    *,
    backend: _Backend = "cpu",
    behaviour: _Behaviour = None,
    max_pixels: float = 1e11,
) -> Image:
    """The target of a scene file, as ``pointillist render`` writes it; a draw beyond
    ``max_pixels`` pixels is refused (SceneError) before it is drawn."""

def animate(
    path: str,
    out: str,
    *,
    frames: Optional[int] = None,
    backend: _Backend = "cpu",
    behaviour: _Behaviour = None,
    max_pixels: float = 1e11,
) -> None:
    """Every frame of a scene's animation to a file, as ``pointillist animate`` writes it."""

def lanes() -> Literal["avx512", "avx2", "sse2", "portable"]:
    """The vector level of the CPU backend's wide spans."""

def behaviours_table() -> list[dict[str, object]]:
    """The device behaviour switches, as ``pointillist behaviours --json`` lists them."""

def behaviour_profiles() -> list[dict[str, object]]:
    """The behaviour profiles, as ``pointillist behaviours --profiles --json`` lists them."""

@final
class Device:
    """A Direct3D 9 device drawing point lists (IDirect3DDevice9's point calls)."""

    def __new__(
        cls,
        width: int,
        height: int,
        backend: _Backend = "cpu",
        *,
        api: Literal["d3d9", "d3d8"] = "d3d9",
        caps: str = "reference",
        clear: int = 0xFF000000,
        behaviour: _Behaviour = None,
    ) -> "Device": ...
    @property
    def size(self) -> Tuple[int, int]:
        """The target's (width, height)."""
    @property
    def behaviour(self) -> dict[str, str]:
        """Every behaviour switch's option, by name."""
    def set_render_state(self, name: str, value: _StateValue) -> None:
        """SetRenderState."""
    def render_state(self, name: str) -> int:
        """GetRenderState: the raw 32 bits."""
    def set_texture_stage_state(self, stage: int, name: str, value: _StateValue) -> None:
        """SetTextureStageState."""
    def set_sampler_state(self, sampler: int, name: str, value: _StateValue) -> None:
        """SetSamplerState."""
    def set_texture(self, stage: int, array: Optional[_U8Array]) -> None:
        """SetTexture from an (h, w, 4) uint8 RGBA array; None unbinds."""
    def set_transform(
        self, name: str, matrix: Union[npt.ArrayLike, Sequence[Sequence[float]]]
    ) -> None:
        """SetTransform("world" | "view" | "projection", 4x4 rows)."""
    def set_viewport(
        self, x: int, y: int, width: int, height: int, min_z: float = 0.0, max_z: float = 1.0
    ) -> None:
        """SetViewport."""
    def set_clip_plane(self, index: int, plane: Sequence[float]) -> None:
        """SetClipPlane."""
    def clear(self, color: int = 0xFF000000, depth: float = 1.0) -> None:
        """Clear of the target and the depth buffer."""
    def draw_points(
        self, fvf: Union[str, int], vertices: Union[bytes, bytearray, memoryview, npt.NDArray]
    ) -> None:
        """DrawPrimitiveUP(D3DPT_POINTLIST) of vertices laid out as the FVF says."""
    def read_target(self) -> Image:
        """The target as an (h, w, 4) uint8 RGBA array."""
    def take_notices(self) -> list[str]:
        """States set that have no effect on points, once each."""

# The steps of pointillist.dask.

def _check(plot: Plot, columns: _Columns) -> None:
    """Checks the columns against the plot without drawing."""

def _partial(plot: Plot, columns: _Columns, threads: Optional[int] = None) -> Image:
    """The points drawn onto a zero target (a blend that commutes, no depth)."""

def _counts(
    plot: Plot,
    columns: _Columns,
    out: Optional[npt.NDArray[numpy.uint8]] = None,
    threads: Optional[int] = None,
) -> Optional[npt.NDArray[numpy.uint8]]:
    """The (height, width) counts of a counted draw, added to ``out`` when given; None when
    the draw is not counted."""

def _add_counts(dst: npt.NDArray[numpy.uint8], src: npt.NDArray[numpy.uint8]) -> None:
    """``dst += src`` in place, saturating at 255."""

def _from_counts(plot: Plot, counts: npt.NDArray[numpy.uint8], columns: _Columns) -> Image:
    """The image of a counted draw from its counts."""

def _combine(dst: _U8Array, src: _U8Array, plot: Plot) -> None:
    """Combines partial image ``src`` into ``dst`` with the blend's exact operator."""

def _finish(rgba: _U8Array, plot: Plot) -> None:
    """Combines the clear colour into the combined partial images, in place."""

def _tiles(plot: Plot, tile_width: int, tile_height: int) -> list[_Rect]:
    """The tiles of the target, ``(x0, y0, x1, y1)`` row by row."""

def _bin(
    plot: Plot, columns: _Columns, first_index: int, tile_width: int, tile_height: int
) -> list[Tuple[npt.NDArray[numpy.uint32], npt.NDArray[numpy.uint64]]]:
    """Each tile's vertices and indices of the points whose squares overlap it."""

def _render_tile(
    plot: Plot,
    vertices: npt.NDArray[numpy.uint32],
    rect: _Rect,
    *,
    size: Optional[float],
    depth: bool,
) -> Image:
    """One tile's (h, w, 4) RGBA from its vertices, in index order."""

def _encode_png(rgba: _U8Array) -> bytes:
    """PNG bytes of an (h, w, 4) uint8 RGBA array."""

def _save_png(path: str, rgba: _U8Array) -> None:
    """Writes an (h, w, 4) uint8 RGBA array as a PNG file, atomically."""
