"""Rendering to numpy images."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Optional

import numpy as np

from . import _native
from ._native import Patches
from ._point_cloud import PointCloud
from ._prep import prep
from ._scene import Scene


class RenderedImage(np.ndarray):
    """An (H, W, 4) float32 image: linear RGB, and alpha 1 where a primary ray hit the scene.

    It is a numpy array. ``aovs`` holds the arbitrary output variables when they were asked
    for: ``depth`` (H, W; ``inf`` where nothing was hit), ``normal`` (H, W, 3), ``instance``
    and ``primitive`` (H, W int64; -1 where nothing was hit), and under the path integrator
    ``albedo`` (H, W, 3). In a notebook it shows as the PNG
    ``pointray render`` would write.
    """

    aovs: Optional[dict[str, np.ndarray]]

    def __array_finalize__(self, obj: Any) -> None:
        self.aovs = getattr(obj, "aovs", None)

    def _repr_png_(self) -> bytes:
        return png_bytes(self)

    def save(self, path: str | os.PathLike) -> None:
        """Writes the image as ``pointray render -o`` does: ``.png`` (8-bit sRGB) or ``.exr``
        (linear float), atomically."""
        _native.save_image(np.ascontiguousarray(self, dtype=np.float32), os.fspath(path))


def png_bytes(image: np.ndarray) -> bytes:
    """An (H, W, 3 or 4) linear float image as 8-bit sRGB PNG bytes (alpha dropped)."""
    return _native.encode_png(np.ascontiguousarray(image, dtype=np.float32))


def render(source: Scene | str | os.PathLike | PointCloud | Patches | np.ndarray, *,
           width: Optional[int] = None, height: Optional[int] = None, spp: Optional[int] = None,
           max_depth: Optional[int] = None, shadows: Optional[bool] = None,
           integrator: Optional[str] = None, seed: Optional[int] = None,
           patches_per_box: Optional[int] = None, hot_records: Optional[str] = None,
           backend: str = "auto",
           device: str = "auto", gpu_memory: Optional[int | str] = None,
           camera: Optional[dict[str, Any]] = None, aovs: bool = False,
           denoise: bool = False, up: Optional[str] = None, floor: bool = True,
           color: str = "auto") -> RenderedImage:
    """Renders a scene or points, as ``pointray render`` does, to a :class:`RenderedImage`.

    ``source`` is a :class:`Scene`, a scene file (``.toml``), a points file or patch store, a
    :class:`PointCloud`, :class:`Patches` or an (N, 3) array of positions. Points are shown as
    ``pointray render POINTS`` shows them: stood upright by ``up`` (``"y"`` or ``"z"``; by
    default the file format's convention, and ``"y"`` for arrays), on a ``floor``, coloured by
    ``color`` (``"auto"``: their RGB, else their intensity, else grey; or ``"points"``,
    ``"intensity"``, ``"height"``, ``"classification"``, ``"fixed"``), lit by one light and
    framed.

    ``width``, ``height``, ``spp``, ``max_depth``, ``integrator`` (``"whitted"`` or
    ``"path"``), ``seed`` (the path integrator's random sequence) and ``patches_per_box`` (the
    GPU's boxes: one a run of this many patches; by default 1, or 4 where the scene does not
    fit the GPU's memory with 1) and ``hot_records`` (``"packed"`` or ``"unpacked"``: the point
    sets' records on the GPU; by default unpacked for small point sets where the scene fits the
    GPU's memory so) override the scene's ``[render]`` settings; ``backend`` is ``"auto"`` (a
    hardware ray-tracing GPU, else the CPU),
    ``"vulkan"`` or ``"cpu"``; ``gpu_memory`` (bytes, or a size such as ``"40G"``) holds a
    scene to less GPU memory than the device has, as ``--gpu-memory`` does (point sets that do
    not fit stream: the tiles the camera sees are loaded first, and a ``UserWarning`` says what
    the image lacks); ``camera`` is the scene file's camera table (``position``,
    ``look_at``, ``up``, ``vfov_degrees``) in the file's coordinates; ``denoise`` filters the
    noise out of a preview of few samples, as ``pointray render --denoise`` does (the AOVs stay
    unfiltered). The GIL is released while the scene loads and renders.
    """
    image_settings = _native.ImageSettings(width=width, height=height, spp=spp, max_depth=max_depth,
                                           shadows=shadows, integrator=integrator, seed=seed,
                                           patches_per_box=patches_per_box,
                                           hot_records=hot_records)
    options = _native.RenderOptions(image_settings, backend=backend, device=device,
                                    gpu_memory=gpu_memory, camera=camera, denoise=denoise)
    result = _native.render(_source(source, up, floor, color), options)
    image = result.pop("image").view(RenderedImage)
    image.aovs = result if aovs else None
    return image


def _source(source: Any, up: Optional[str], floor: bool, color: str) -> _native.RenderSource:
    look = dict(up=up, floor=floor, color=color)
    if isinstance(source, Scene):
        return _native.RenderSource.scene(source._toml(), str(source._anchor), list(source._in_memory.items()))
    if isinstance(source, (str, os.PathLike)):
        path = Path(source)
        if path.suffix.lower() == ".toml":
            return _source(Scene.from_file(path), up, floor, color)
        return _native.RenderSource.points(points_file=os.fspath(path), **look)
    if isinstance(source, PointCloud):
        look["up"] = up or source.up_axis
        return _native.RenderSource.points(patches=prep(source), **look)
    if isinstance(source, Patches):
        return _native.RenderSource.points(patches=source, **look)
    return _native.RenderSource.points(patches=prep(np.asarray(source)), **look)
