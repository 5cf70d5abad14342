"""Point clouds as smooth, lit, ray-traced surfaces.

Read a scan, turn its points into MLS patches, and render them to numpy images::

    import pointray
    cloud = pointray.read("scan.las")
    image = pointray.render(cloud, width=800, height=600)   # (600, 800, 4) float32, linear RGBA

Every function raises :class:`PointrayError` with the message the ``pointray`` command line
prints for the same failure, and ``ValueError`` or ``TypeError`` for arrays of the wrong shape
or kind.
"""

from ._native import Patches, PointrayError, devices
from ._point_cloud import PointCloud, read, read_sweeps
from ._prep import prep
from ._render import RenderedImage, png_bytes, render
from ._scene import Scene

__all__ = ["Patches", "PointCloud", "PointrayError", "RenderedImage", "Scene", "devices", "png_bytes",
           "prep", "read", "read_sweeps", "render"]
