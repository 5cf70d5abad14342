"""Point clouds as smooth, lit, ray-traced surfaces.

Read a scan, turn its points into MLS patches, and render them to numpy images::

    import pointray
    cloud = pointray.read("scan.las")
    image = pointray.render(cloud, width=800, height=600)   # (600, 800, 4) float32, linear RGBA

Large clouds prep as tile jobs on a cluster: :func:`prep_tile` and :func:`merge_tiles` are
``pointray prep --tile I --of N`` and ``--merge``, and :func:`dask_prep` maps them over a
``dask.distributed`` client.

Every function raises :class:`PointrayError` with the message the ``pointray`` command line
prints for the same failure, and ``ValueError`` or ``TypeError`` for arrays of the wrong shape
or kind.
"""

from ._dask_prep import dask_prep
from ._native import Patches, PointrayError, devices
from ._point_cloud import PointCloud, read, read_sweeps
from ._prep import prep
from ._render import RenderedImage, png_bytes, render
from ._scene import Scene
from ._tiles import merge_tiles, prep_tile

__all__ = ["Patches", "PointCloud", "PointrayError", "RenderedImage", "Scene", "dask_prep", "devices",
           "merge_tiles", "png_bytes", "prep", "prep_tile", "read", "read_sweeps", "render"]
