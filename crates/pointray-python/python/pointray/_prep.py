"""Points to patches."""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

from . import _native
from ._native import Patches
from ._point_cloud import PointCloud

_ATTRIBUTES = ("colors", "normals", "intensity", "classification", "ring", "sensor_position", "sensor_origins")


def prep(points: PointCloud | np.ndarray, *, colors: Optional[np.ndarray] = None,
         normals: Optional[np.ndarray] = None, intensity: Optional[np.ndarray] = None,
         classification: Optional[np.ndarray] = None, ring: Optional[np.ndarray] = None,
         sensor_position: Optional[Any] = None, **settings: Any) -> Patches:
    """Fits one MLS patch to every distinct point, as ``pointray prep`` does.

    ``points`` is a :class:`PointCloud` (its attributes come along) or an (N, 3) array of any
    float or integer dtype (float64 keeps geo-referenced coordinates exact). Per-point
    ``colors`` (uint8 sRGB, N x 3), ``normals``, ``intensity`` (0..1), ``classification``
    (ASPRS codes) and ``ring`` (scan line), and the scanner's ``sensor_position``, override
    the cloud's own.

    ``settings`` are ``pointray prep``'s flags by name: ``k``, ``normal_k``,
    ``recompute_normals``, ``sensor`` (x, y, z), ``remove_outliers`` (``{"neighbors": 8,
    "sigmas": 2.0}``), ``radius`` (``"cell"``, ``"paper"``, ``"adaptive"``), ``disk_scale``,
    ``boxes`` (``"tight"``, ``"cube"``), ``scan`` (``"auto"``, ``"off"``).

    The GIL is released while prep runs.
    """
    given = dict(colors=colors, normals=normals, intensity=intensity,
                 classification=classification, ring=ring, sensor_position=sensor_position)
    if isinstance(points, PointCloud):
        attributes = {name: getattr(points, name) for name in _ATTRIBUTES}
        attributes.update({name: value for name, value in given.items() if value is not None})
        positions = points.positions
    else:
        attributes, positions = given, points
    if attributes.get("sensor_position") is not None:
        attributes["sensor_position"] = tuple(float(c) for c in np.asarray(attributes["sensor_position"]).ravel())
    return _native.prep(positions, _native.PointAttributes(**attributes), _native.PrepOptions(**settings))
