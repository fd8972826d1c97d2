"""Type stubs of the pointillist package (see the module's docstring at run time)."""

import os
from typing import Literal, Optional, Sequence, Tuple, Union

import numpy
import numpy.typing as npt

from ._image import Image as Image

__all__ = [
    "Device",
    "Error",
    "Image",
    "SceneError",
    "animate",
    "lanes",
    "points",
    "render_scene",
]

Blend = Literal["add", "alpha", "max", "replace"]
Backend = Literal["cpu", "gpu"]
Number = Union[int, float, numpy.number]
Column = npt.ArrayLike
Range = Optional[Tuple[float, float]]
StateValue = Union[float, int, bool, str]

class Error(Exception):
    """A call the device refused or a draw that failed; the message is the CLI's one line."""

class SceneError(Error):
    """A scene file that cannot be read or drawn (file, line, column and key)."""

def points(
    x: Column,
    y: Column,
    *,
    size: Union[Number, Column] = 1.0,
    color: Union[int, Column] = 0xFFFFFFFF,
    z: Optional[Column] = None,
    width: int,
    height: int,
    blend: Blend = "add",
    x_range: Range = None,
    y_range: Range = None,
    clear: int = 0xFF000000,
    texture: Optional[npt.NDArray[numpy.uint8]] = None,
    backend: Backend = "cpu",
) -> Image:
    """One point sprite per row of ``x, y``; the ``(height, width, 4)`` uint8 RGBA image."""

def render_scene(
    path: Union[str, os.PathLike[str]],
    frame: Optional[int] = None,
    *,
    backend: Backend = "cpu",
    behaviour: Optional[dict[str, str]] = None,
    max_pixels: float = 1e11,
) -> Image:
    """The target of a scene file, as ``pointillist render`` writes it; a draw beyond
    ``max_pixels`` pixels is refused (SceneError) before it is drawn."""

def animate(
    path: Union[str, os.PathLike[str]],
    out: Union[str, os.PathLike[str]],
    *,
    frames: Optional[int] = None,
    backend: Backend = "cpu",
    behaviour: Optional[dict[str, str]] = None,
    max_pixels: float = 1e11,
) -> None:
    """Every frame of a scene's animation to a GIF, APNG, PNG sequence or MP4, as
    ``pointillist animate`` writes it; whole or not at all (SceneError, KeyboardInterrupt)."""

def lanes() -> str:
    """The vector level of the CPU backend's wide spans."""

def behaviours() -> list[dict[str, object]]:
    """The device behaviour switches, as ``pointillist behaviours --json`` lists them."""

def behaviour_profiles() -> list[dict[str, object]]:
    """The behaviour profiles, as ``pointillist behaviours --profiles --json`` lists them."""

class Device:
    """A Direct3D 9 device drawing point lists (IDirect3DDevice9's point calls)."""

    def __init__(
        self,
        width: int,
        height: int,
        backend: Backend = "cpu",
        *,
        api: Literal["d3d9", "d3d8"] = "d3d9",
        caps: str = "reference",
        clear: int = 0xFF000000,
    ) -> None: ...
    @property
    def size(self) -> Tuple[int, int]:
        """The target's (width, height)."""
    def set_render_state(self, name: str, value: StateValue) -> None:
        """SetRenderState."""
    def render_state(self, name: str) -> int:
        """GetRenderState: the raw 32 bits."""
    def set_texture_stage_state(self, stage: int, name: str, value: StateValue) -> None:
        """SetTextureStageState."""
    def set_sampler_state(self, sampler: int, name: str, value: StateValue) -> None:
        """SetSamplerState."""
    def set_texture(self, stage: int, array: Optional[npt.NDArray[numpy.uint8]]) -> None:
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
