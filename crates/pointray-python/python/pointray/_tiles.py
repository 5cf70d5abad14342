"""Prep cut into tile jobs, for a cluster: the jobs ``pointray prep --tile I --of N`` and
``pointray prep --merge`` run, from Python."""

from __future__ import annotations

import os
from typing import Any, Iterable, Optional

from . import _native

PathLike = str | os.PathLike


def prep_tile(points_path: PathLike, tile: int, of: int, output: PathLike, *,
              memory: Optional[str] = None, columns: Optional[str] = None, **settings: Any) -> int:
    """Preps tile ``tile`` (0 to ``of`` - 1) of the ``of`` tiles the points file is cut into,
    and writes it alone to the tile file ``output``, as ``pointray prep POINTS --tile I --of N``
    does. Returns the number of points the tile owns.

    Every job of one cut reads and sorts the shared input the same way, so jobs on separate
    processes or machines agree on the cut. ``memory`` is the budget (``"8G"``, ``"512M"``;
    default half the machine's RAM), ``columns`` names a text or ``.bin`` file's columns, and
    ``settings`` are :func:`pointray.prep`'s. The GIL is released while the tile preps.
    """
    options = _native.PrepOptions(**settings)
    return _native.prep_tile(os.fspath(points_path), (tile, of), os.fspath(output), options,
                             memory=memory, columns=columns)


def merge_tiles(tile_paths: Iterable[PathLike], output: PathLike, *, memory: Optional[str] = None,
                remove_tiles: bool = False) -> int:
    """Merges tile files (every tile of one cut, once each, in any order) into the patch store
    ``output``: the bytes ``pointray prep --tiles N`` writes in one process, as
    ``pointray prep --merge`` writes them. Returns the number of patches.

    ``remove_tiles`` removes each tile file as soon as its records are in the store, once
    every tile has been read and checked (``prep --merge --remove-tiles``): for a disk that
    cannot hold the tiles and the store at once. A merge that fails after that leaves the
    removed tiles to be prepped again."""
    return _native.merge_tiles([os.fspath(path) for path in tile_paths], os.fspath(output), memory=memory,
                               remove_tiles=remove_tiles)
