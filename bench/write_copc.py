"""Writes a COPC file (LAS 1.4, point format 6) of the points of a binary PLY file, with
copclib: the stand-in that `pointray prep`'s COPC timings read.

The octree has the levels of detail COPC writers give: every level holds a share of the
points spread over the whole cloud (chosen by a seeded shuffle), the share of level l in
proportion to 4^l, as the occupied nodes of a surface grow, down to the level where a node
holds about NODE_POINTS points. Every point lands in the node of its level whose box holds
it. The attributes are filled as a LiDAR tile's are: intensities run with height over the
8-bit range, GPS times with the points' order in the input (a microsecond apart), scan
angles with their x, and every point is the one return of its pulse from source 1.

Needs `pip install copclib==2.6.3 numpy`.

    python bench/write_copc.py POINTS.ply OUT.copc.laz
"""

import math
import sys

import copclib
import numpy as np

NODE_POINTS = 100_000
SEED = 1
# Point format 6: X, Y, Z (i32), intensity (u16), returns, flags, class, user data (u8 each),
# scan angle (i16), point source (u16), GPS time (f64).
RECORD = np.dtype(
    [
        ("x", "<i4"),
        ("y", "<i4"),
        ("z", "<i4"),
        ("intensity", "<u2"),
        ("returns", "u1"),
        ("flags", "u1"),
        ("classification", "u1"),
        ("user_data", "u1"),
        ("scan_angle", "<i2"),
        ("point_source", "<u2"),
        ("gps_time", "<f8"),
    ]
)
PLY_TYPES = {"float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8", "uchar": "u1", "uint8": "u1"}


def read_ply_positions(path):
    with open(path, "rb") as file:
        count, fields = 0, []
        while (line := file.readline().decode("ascii").strip()) != "end_header":
            words = line.split()
            if words[:2] == ["element", "vertex"]:
                count = int(words[2])
            elif words[:1] == ["property"]:
                fields.append((words[2], PLY_TYPES[words[1]]))
        vertices = np.fromfile(file, dtype=np.dtype(fields), count=count)
    return np.stack([vertices["x"], vertices["y"], vertices["z"]], axis=1).astype(np.float64)


def levels_of(count, rng):
    depth = max(1, math.ceil(math.log(max(count / NODE_POINTS, 1), 4)))
    weights = np.array([4.0**level for level in range(depth + 1)])
    shares = np.floor(weights / weights.sum() * count).astype(np.int64)
    shares[-1] += count - shares.sum()
    levels = np.repeat(np.arange(depth + 1, dtype=np.int32), shares)
    rng.shuffle(levels)
    return levels


def main():
    source, target = sys.argv[1], sys.argv[2]
    xyz = read_ply_positions(source)
    low, high = xyz.min(axis=0), xyz.max(axis=0)
    extent = float((high - low).max())
    scale = 10.0 ** math.floor(math.log10(extent / 1e6))
    centre = (low + high) / 2
    halfsize = extent / 2 + scale
    config = copclib.CopcConfigWriter(6, copclib.Vector3(scale, scale, scale), copclib.Vector3(*centre))
    header = config.las_header
    header.min = copclib.Vector3(*low)
    header.max = copclib.Vector3(*high)
    info = config.copc_info
    info.center_x, info.center_y, info.center_z = (float(c) for c in centre)
    info.halfsize = halfsize
    info.spacing = 2 * halfsize / 128

    rng = np.random.default_rng(SEED)
    levels = levels_of(len(xyz), rng)
    unit = (xyz - (centre - halfsize)) / (2 * halfsize)
    cells = np.clip(np.floor(unit * (1 << levels)[:, None]).astype(np.int64), 0, (1 << levels)[:, None] - 1)
    keys = np.stack([levels, cells[:, 0], cells[:, 1], cells[:, 2]], axis=1)
    order = np.lexsort((keys[:, 3], keys[:, 2], keys[:, 1], keys[:, 0]))

    records = np.zeros(len(xyz), dtype=RECORD)
    quantised = np.round((xyz - centre) / scale).astype(np.int32)
    records["x"], records["y"], records["z"] = quantised[:, 0], quantised[:, 1], quantised[:, 2]
    records["intensity"] = np.round((xyz[:, 2] - low[2]) / max(high[2] - low[2], scale) * 255).astype(np.uint16)
    records["returns"] = 0x11
    records["gps_time"] = 3.0e8 + np.arange(len(xyz)) * 1e-6
    records["scan_angle"] = np.round((unit[:, 0] - 0.5) * 6000).astype(np.int16)
    records["point_source"] = 1
    records = records[order]
    keys = keys[order]

    starts = np.flatnonzero(np.any(keys[1:] != keys[:-1], axis=1)) + 1
    bounds = np.concatenate([[0], starts, [len(keys)]])
    writer = copclib.FileWriter(target, config)
    for start, end in zip(bounds[:-1], bounds[1:]):
        level, x, y, z = (int(v) for v in keys[start])
        data = copclib.VectorChar(records[start:end].view(np.int8))
        writer.AddNode(copclib.VoxelKey(level, x, y, z), data)
    writer.Close()
    print(f"wrote {target}: {len(xyz)} points in {len(bounds) - 1} nodes, {int(levels.max()) + 1} levels", file=sys.stderr)


if __name__ == "__main__":
    main()
