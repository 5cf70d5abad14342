"""Writes data/scans/autzen_trim.copc.laz from data/scans/autzen_trim.las with copclib.

The octree is 4 levels deep: a fixed share of the points (chosen by input index, so
the file is the same on every run) sits at each coarser level, the rest at the finest.
Every point lands in the node of its level whose box contains it, as COPC requires.

Needs `pip install copclib==2.6.3 laspy==2.7.0 numpy`; run from the repository root. The
Python package's tests write the tile again with `write_copc`, into a scratch folder.
"""

import sys

import copclib
import laspy
import numpy as np

SOURCE = "data/scans/autzen_trim.las"
TARGET = "data/scans/autzen_trim.copc.laz"
FINEST_LEVEL = 3
# Every 64th point at level 0, every 16th (of the rest) at 1, every 4th at 2.
LEVEL_STRIDES = (64, 16, 4)


def level_of(index):
    for level, stride in enumerate(LEVEL_STRIDES):
        if index % stride == 0:
            return level
    return FINEST_LEVEL


def write_copc(source, target):
    """Writes the LAS file `source` as the COPC file `target`; returns the nodes written."""
    las = laspy.read(source)
    xyz = np.stack([las.x, las.y, las.z], axis=1)
    low, high = xyz.min(axis=0), xyz.max(axis=0)
    centre = (low + high) / 2
    halfsize = float((high - low).max()) / 2 + 0.01
    scale = [float(s) for s in las.header.scales]
    offset = [float(o) for o in las.header.offsets]

    config = copclib.CopcConfigWriter(7, copclib.Vector3(*scale), copclib.Vector3(*offset))
    header = config.las_header
    header.min = copclib.Vector3(*low)
    header.max = copclib.Vector3(*high)
    info = config.copc_info
    info.center_x, info.center_y, info.center_z = (float(c) for c in centre)
    info.halfsize = halfsize
    info.spacing = 2 * halfsize / 64

    nodes = {}
    for index in range(len(xyz)):
        level = level_of(index)
        cells = 2**level
        cell = np.floor((xyz[index] - (centre - halfsize)) / (2 * halfsize) * cells).astype(int)
        cell = np.clip(cell, 0, cells - 1)
        nodes.setdefault((level, *cell.tolist()), []).append(index)

    writer = copclib.FileWriter(str(target), config)
    for (level, x, y, z), indices in sorted(nodes.items()):
        points = copclib.Points(writer.copc_config.las_header)
        for index in indices:
            point = points.CreatePoint()
            point.x, point.y, point.z = (float(v) for v in xyz[index])
            point.intensity = int(las.intensity[index])
            point.gps_time = float(las.gps_time[index])
            point.classification = int(las.classification[index])
            point.return_number = max(1, int(las.return_number[index]))
            point.number_of_returns = max(1, int(las.number_of_returns[index]))
            point.red = int(las.red[index])
            point.green = int(las.green[index])
            point.blue = int(las.blue[index])
            points.AddPoint(point)
        writer.AddNode(copclib.VoxelKey(level, x, y, z), points)
    writer.Close()
    return len(nodes)


def main():
    nodes = write_copc(SOURCE, TARGET)
    print(f"wrote {TARGET}: {nodes} nodes", file=sys.stderr)


if __name__ == "__main__":
    main()
