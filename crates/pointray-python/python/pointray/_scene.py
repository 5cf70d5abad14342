"""Scenes built in Python, mirroring the scene file (TOML)."""

from __future__ import annotations

import copy
import os
from pathlib import Path
from typing import Any, Optional

import numpy as np

from . import _native
from ._native import Patches, PointrayError
from ._point_cloud import PointCloud


class Scene:
    """A scene: the tables of a scene file, built call by call.

    Each method adds what the scene file's table of the same name holds and returns the scene,
    so calls chain::

        scene = (pointray.Scene()
                 .light("point", position=[1, 2, 1])
                 .points("bunny.ply", material={"diffuse": [0.8, 0.6, 0.4]})
                 .ground(auto=True))

    Points may come from a file or from memory (an array, a :class:`PointCloud` or
    :class:`Patches`); a scene holding points from memory renders but cannot be written as TOML.
    """

    def __init__(self) -> None:
        self._document: dict[str, Any] = {"lights": [], "objects": []}
        self._in_memory: dict[int, Patches] = {}
        self._anchor = Path.cwd() / "(scene from Python)"

    @classmethod
    def from_toml(cls, text: str, path: Optional[str | os.PathLike] = None) -> "Scene":
        """A scene from scene-file text; relative paths resolve against ``path``'s folder (or
        the working directory). Raises :class:`PointrayError` as ``pointray render`` would."""
        scene = cls()
        if path is not None:
            scene._anchor = Path(path).absolute()
        scene._document = _native.scene_from_toml(text, str(scene._anchor))
        scene._document.setdefault("lights", [])
        scene._document.setdefault("objects", [])
        return scene

    @classmethod
    def from_file(cls, path: str | os.PathLike) -> "Scene":
        """Reads a scene file."""
        path = Path(path)
        try:
            text = path.read_text()
        except OSError as error:
            raise PointrayError(f"{path}: {error.strerror or error}") from None
        return cls.from_toml(text, path)

    def to_toml(self) -> str:
        """The scene as a scene file; ``pointray render`` renders it the same."""
        if self._in_memory:
            indices = ", ".join(f"objects[{i}]" for i in sorted(self._in_memory))
            raise PointrayError(f"{indices} hold points from memory, which a scene file cannot; "
                                "save them with Patches.save and add the store's path instead")
        return self._toml()

    def _toml(self) -> str:
        return _native.scene_to_toml(self._document, str(self._anchor))

    def camera(self, position, look_at, *, up=None, vfov_degrees=None) -> "Scene":
        """Where the camera stands and looks (scene coordinates); without it, the scene is framed."""
        self._document["camera"] = _table(position=position, look_at=look_at, up=up, vfov_degrees=vfov_degrees)
        return self

    def light(self, type: str = "point", **fields: Any) -> "Scene":
        """A ``"point"`` light (``position``) or a ``"directional"`` one (``direction``), with
        ``color`` and ``intensity``."""
        self._document["lights"].append(_table(type=type, **fields))
        return self

    def background(self, color=None, *, top=None, bottom=None, map=None, **fields: Any) -> "Scene":
        """A solid colour; a gradient from ``bottom`` to ``top``; an environment ``map`` (an
        equirectangular ``.exr`` or ``.hdr``, with ``intensity`` and ``rotation_degrees``); or a
        procedural sun and sky (``sun_elevation_degrees``, ``sun_azimuth_degrees``,
        ``sun_radius_degrees``, ``sun_intensity``, ``sky_intensity``)."""
        if color is not None:
            self._document["background"] = list(color)
        else:
            path = os.fspath(map) if map is not None else None
            self._document["background"] = _table(top=top, bottom=bottom, map=path, **fields)
        return self

    def render_settings(self, **settings: Any) -> "Scene":
        """The ``[render]`` table: ``width``, ``height``, ``spp``, ``max_depth``."""
        self._document.setdefault("render", {}).update(settings)
        return self

    def points(self, source: str | os.PathLike | np.ndarray | PointCloud | Patches, *, name=None,
               transform=None, material=None, prep=None, columns=None) -> "Scene":
        """A point set: a points file or patch store, or points in memory (prepped now, with
        ``prep``'s settings). ``prep`` is ``pointray prep``'s flags by name."""
        entry = _table(type="points", name=name, transform=transform, material=material, prep=prep, columns=columns)
        if isinstance(source, (str, os.PathLike)):
            entry["path"] = os.fspath(source)
        else:
            from ._prep import prep as prep_points
            patches = source if isinstance(source, Patches) else prep_points(source, **(prep or {}))
            entry.pop("prep", None)
            entry["path"] = f"(points from memory, object {len(self._document['objects'])})"
            self._in_memory[len(self._document["objects"])] = patches
        self._document["objects"].append(entry)
        return self

    def mesh(self, path: str | os.PathLike, *, name=None, transform=None, material=None) -> "Scene":
        """A triangle mesh (PLY or OBJ)."""
        self._document["objects"].append(
            _table(type="mesh", path=os.fspath(path), name=name, transform=transform, material=material))
        return self

    def ground(self, *, auto: bool = True, height=None, size=None, material=None) -> "Scene":
        """A floor under the other objects (``auto``) or at ``height``."""
        self._document["objects"].append(
            _table(type="ground", auto=auto or None, height=height, size=size, material=material))
        return self

    def copy(self) -> "Scene":
        duplicate = Scene()
        duplicate._document = copy.deepcopy(self._document)
        duplicate._in_memory = dict(self._in_memory)
        duplicate._anchor = self._anchor
        return duplicate

    def __repr__(self) -> str:
        kinds = [obj.get("type", "?") for obj in self._document["objects"]]
        return f"Scene(objects={kinds}, lights={len(self._document['lights'])})"


def _table(**fields: Any) -> dict[str, Any]:
    """The fields given, leaving out those left as ``None``."""
    return {key: value for key, value in fields.items() if value is not None}
