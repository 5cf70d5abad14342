"""Prep fanned out over a Dask cluster: one task per tile, then the merge."""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path
from typing import Any, Optional

from . import _native
from ._tiles import PathLike, merge_tiles, prep_tile


def dask_prep(points_path: PathLike, output: PathLike, *, tiles: int, client: Any = None,
              memory: Optional[str] = None, columns: Optional[str] = None, **settings: Any) -> int:
    """Preps a points file in ``tiles`` tile jobs mapped over a ``dask.distributed``
    ``client`` (default: the current client), merges them into the patch store ``output``, and
    returns its number of patches. The store is the one ``pointray prep --tiles N`` writes.

    The tile files go to a folder made beside ``output`` and removed at the end, so the input,
    that folder and ``output`` must lie on a file system every worker sees. ``memory`` is each
    tile job's budget (``"8G"``); ``columns`` and ``settings`` are :func:`pointray.prep_tile`'s.

    Needs Dask's distributed scheduler (``pip install "dask[distributed]"``).
    """
    try:
        import distributed
    except ImportError as missing:
        raise ImportError('pointray.dask_prep needs Dask\'s distributed scheduler: '
                          'pip install "dask[distributed]"') from missing
    if tiles < 1:
        raise ValueError(f"tiles: {tiles}; prep needs at least one tile")
    client = client if client is not None else _current_client(distributed)
    points_path, output = Path(points_path), Path(output)
    _native.PrepOptions(**settings)  # bad settings fail here, not in every worker
    _ensure_output_spares_input(points_path, output)
    folder = Path(tempfile.mkdtemp(prefix=f".{output.name}.tiles-", dir=output.parent))
    try:
        tile_paths = [folder / f"{index}.tile" for index in range(tiles)]
        jobs = [client.submit(prep_tile, points_path, index, tiles, path, memory=memory, columns=columns,
                              pure=False, **settings)
                for index, path in enumerate(tile_paths)]
        # The merge waits on the tile jobs through their futures, and runs on a worker too.
        merged = client.submit(_merge_after, jobs, tile_paths, output, memory, pure=False)
        return merged.result()
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _current_client(distributed: Any) -> Any:
    try:
        return distributed.get_client()
    except ValueError as none:
        raise ValueError("pointray.dask_prep needs a dask.distributed Client: pass client=, "
                         "or make one first") from none


def _ensure_output_spares_input(points_path: Path, output: Path) -> None:
    """The checks ``pointray prep`` makes before it starts, here before any job starts."""
    if not output.parent.is_dir():
        raise _native.PointrayError(f"{output}: its folder {output.parent} does not exist")
    if output.exists() and points_path.exists() and os.path.samefile(points_path, output):
        raise _native.PointrayError(f"{output}: refusing to write over the input file {points_path}")


def _merge_after(_tile_jobs: list[int], tile_paths: list[Path], output: Path, memory: Optional[str]) -> int:
    # The tile files are this function's own, removed at the end either way: removed as they
    # are merged, the store and the tiles need not fit the disk at once.
    return merge_tiles(tile_paths, output, memory=memory, remove_tiles=True)
