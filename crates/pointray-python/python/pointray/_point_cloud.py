"""Points read from a file, as numpy arrays."""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Optional

import numpy as np

from . import _native


@dataclass(frozen=True)
class PointCloud:
    """A point cloud as read from a file.

    ``positions`` are in the file's own coordinates, in float64: geo-referenced scans keep their
    centimetres. Fields the file does not carry are ``None``.
    """

    positions: np.ndarray
    """(N, 3) float64 coordinates."""
    normals: Optional[np.ndarray] = None
    """(N, 3) float32 normals, when the file carries them (not necessarily unit length)."""
    colors: Optional[np.ndarray] = None
    """(N, 3) uint8 sRGB colours."""
    intensity: Optional[np.ndarray] = None
    """(N,) float32 intensities, normalised to [0, 1]."""
    classification: Optional[np.ndarray] = None
    """(N,) uint8 ASPRS classification codes (LAS)."""
    ring: Optional[np.ndarray] = None
    """(N,) uint16 scan line: a spinning sensor's beam, or a scanner's grid row."""
    sensor_position: Optional[tuple] = None
    """Where the scanner stood, when the file says so."""
    sensor_origins: Optional[np.ndarray] = None
    """(N, 3) float64 per-point sensor positions, for merged stations or a moving sensor."""
    up_axis: str = "y"
    """The file format's up axis by convention: ``"z"`` for LAS, LAZ, E57, PCD and ``.bin``
    sweeps, ``"y"`` for PLY, OBJ and text. ``render`` stands the cloud upright by it."""

    def __len__(self) -> int:
        return len(self.positions)

    @property
    def offset(self) -> np.ndarray:
        """The recentring offset, which ``prep`` subtracts (in float64) before anything becomes
        float32: on each axis, the middle of the points' range with the outermost percent left
        out, so that one stray point far off does not move it."""
        return np.array(_native.recentring_offset(self.positions))

    def __repr__(self) -> str:
        fields = [name for name in ("normals", "colors", "intensity", "classification", "ring")
                  if getattr(self, name) is not None]
        return f"PointCloud({len(self)} points, fields: {', '.join(['positions', *fields])})"


def read(path: str | os.PathLike, columns: Optional[str] = None) -> PointCloud:
    """Reads a points file: PLY, LAS/LAZ, E57, PCD, XYZ/PTS/TXT/CSV, KITTI ``.bin`` or nuScenes
    ``.pcd.bin``, OBJ vertices.

    ``columns`` says what each column holds where the format does not name its columns (text
    points and raw ``.bin`` sweeps), as the command line's ``--columns``, e.g. ``"x,y,z,intensity,ring"``.
    """
    return PointCloud(**_native.read(os.fspath(path), columns))


def read_sweeps(paths: list, poses: str | os.PathLike, columns: Optional[str] = None) -> PointCloud:
    """Reads several sweeps and places them into one map by their sensor poses.

    ``poses`` is a poses file: one pose a line, KITTI's 3x4 row-major matrix or a 4x4 one. With
    one pose per sweep the sweeps take them in order; otherwise each sweep takes the line its
    file name numbers (``scan02.bin`` takes line 2). Each point keeps its sweep's sensor origin
    (``sensor_origins``) and its scan line, so ``prep`` shapes every sweep's patches along its
    own lines.
    """
    return PointCloud(**_native.read_sweeps([os.fspath(p) for p in paths], os.fspath(poses), columns))
