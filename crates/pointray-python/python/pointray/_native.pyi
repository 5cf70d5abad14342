"""Type stubs of the extension module; the public API is re-exported by ``pointray``."""

import os
from typing import Any

import numpy as np

class PointrayError(Exception):
    """A pointray operation failed; the message names the file and the problem."""

class Patches:
    """One MLS patch per distinct point: what ``prep`` makes and the renderers draw."""

    @staticmethod
    def load(path: str | os.PathLike[str]) -> Patches:
        """Reads a patch store (``.patches``) that ``pointray prep`` or ``Patches.save`` wrote."""
    def save(self, path: str | os.PathLike[str]) -> None:
        """Writes a patch store, atomically."""
    def __len__(self) -> int: ...
    @property
    def offset(self) -> tuple[float, float, float]:
        """The recentring offset: ``centers = local + offset``, in float64."""
    @property
    def centers(self) -> np.ndarray:
        """(N, 3) float64: each patch's origin, in the input's coordinates: its point moved
        along the normal onto the fitted surface."""
    @property
    def normals(self) -> np.ndarray:
        """(N, 3) float32 unit normals."""
    @property
    def radii(self) -> np.ndarray:
        """(N,) float32 support radii."""

class PrepOptions:
    """``pointray prep``'s settings by the flags' names (``k``, ``normal_k``, ``radius``, ...),
    parsed as a scene file's ``prep`` table is and checked when made: a bad one raises
    ``PointrayError``."""

    def __init__(self, **settings: Any) -> None: ...

class ImageSettings:
    """The scene's ``[render]`` settings one ``render`` call overrides, each checked when made:
    a bad one raises ``ValueError`` naming it. ``None`` leaves the scene's setting as it is."""

    def __init__(self, *, width: int | None = None, height: int | None = None,
                 spp: int | None = None, max_depth: int | None = None,
                 shadows: bool | None = None, integrator: str | None = None,
                 seed: int | None = None, patches_per_box: int | None = None,
                 hot_records: str | None = None) -> None: ...
    @property
    def width(self) -> int | None: ...
    @property
    def height(self) -> int | None: ...
    @property
    def spp(self) -> int | None: ...
    @property
    def max_depth(self) -> int | None: ...
    @property
    def shadows(self) -> bool | None: ...
    @property
    def seed(self) -> int | None: ...
    @property
    def patches_per_box(self) -> int | None: ...

class PointAttributes:
    """What ``prep`` takes beside the positions, read and checked when made: per-point
    ``colors`` (sRGB, N x 3), ``normals`` (N x 3), ``intensity`` (0..1), ``classification``
    (ASPRS codes), ``ring`` (scan line) and ``sensor_origins`` (N x 3), and the one
    ``sensor_position``. A bad array raises ``ValueError`` naming it; one of the wrong length,
    when ``prep`` meets the positions."""

    def __init__(self, *, colors: Any = None, normals: Any = None, intensity: Any = None,
                 classification: Any = None, ring: Any = None,
                 sensor_position: tuple[float, float, float] | None = None,
                 sensor_origins: Any = None) -> None: ...

class RenderOptions:
    """What ``pointray.render``'s keywords become: the ``image`` settings, where it renders,
    the camera and the denoiser, each checked when made: a bad one raises ``ValueError`` naming
    it (``camera``, a bad table: ``PointrayError``)."""

    def __init__(self, image: ImageSettings, *, backend: str = "auto", device: str = "auto",
                 gpu_memory: int | str | None = None, camera: dict[str, Any] | None = None,
                 denoise: bool = False) -> None: ...
    @property
    def gpu_memory(self) -> int | None:
        """The GPU memory budget in bytes."""
    @property
    def denoise(self) -> bool: ...

class RenderSource:
    """What one ``render`` call draws, checked when made: a scene, or points shown as
    ``pointray render POINTS`` shows them."""

    @staticmethod
    def scene(text: str, anchor: str, in_memory: list[tuple[int, Patches]]) -> RenderSource:
        """A scene file's ``text``, its relative paths taken from ``anchor``'s folder, with
        ``in_memory``'s patches standing for the point sets of those object indices."""
    @staticmethod
    def points(*, points_file: str | None = None, patches: Patches | None = None,
               up: str | None = None, floor: bool = True, color: str = "auto") -> RenderSource:
        """Points from ``points_file`` or ``patches``, stood upright by ``up`` (``"y"`` or
        ``"z"``), on a ``floor``, coloured by ``color``, lit by one light and framed."""

def devices() -> list[dict[str, Any]]:
    """The Vulkan devices the loader sees: ``index``, ``name``, ``type``, ``api_version``,
    ``driver``, ``usable``, ``rejection`` (why not, or ``None``) and ``device_local_bytes``."""

def read(path: str, columns: str | None) -> dict[str, Any]: ...
def read_sweeps(paths: list[str], poses: str, columns: str | None) -> dict[str, Any]: ...
def recentring_offset(positions: np.ndarray) -> tuple[float, float, float]: ...
def prep(positions: Any, attributes: PointAttributes, options: PrepOptions) -> Patches: ...
def prep_tile(points_path: str, cut: tuple[int, int], output: str, options: PrepOptions,
              memory: str | None = None, columns: str | None = None) -> int: ...
def merge_tiles(tile_paths: list[str], output: str, memory: str | None = None,
                remove_tiles: bool = False) -> int: ...
def render(source: RenderSource, options: RenderOptions) -> dict[str, np.ndarray]: ...
def scene_to_toml(scene: dict[str, Any], anchor: str) -> str: ...
def scene_from_toml(text: str, anchor: str) -> dict[str, Any]: ...
def encode_png(image: np.ndarray) -> bytes: ...
def save_image(image: np.ndarray, path: str) -> None: ...
