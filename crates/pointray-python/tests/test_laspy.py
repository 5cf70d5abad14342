"""A LAS tile read with laspy and passed as arrays preps as `pointray prep` preps the file."""

import laspy
import numpy as np
import pointray

from conftest import pointray_cli


def test_laspy_arrays_make_the_same_patches_as_the_file(autzen, tmp_path):
    las = laspy.read(autzen)
    positions = np.column_stack([las.x, las.y, las.z])
    rgb = np.column_stack([las.red, las.green, las.blue])
    colors = (rgb >> 8 if rgb.max() > 255 else rgb).astype(np.uint8)
    from_arrays = pointray.prep(positions, colors=colors)
    pointray_cli("prep", autzen, "-o", "cli.patches", cwd=tmp_path)
    from_file = pointray.Patches.load(tmp_path / "cli.patches")
    assert len(from_arrays) == len(from_file)
    assert np.array_equal(from_arrays.centers, from_file.centers)
    assert np.array_equal(from_arrays.normals, from_file.normals)
    assert np.array_equal(from_arrays.radii, from_file.radii)


def test_pointray_reads_what_laspy_reads(autzen):
    las = laspy.read(autzen)
    cloud = pointray.read(autzen)
    assert len(cloud) == len(las.points)
    assert np.allclose(cloud.positions, np.column_stack([las.x, las.y, las.z]), rtol=0, atol=1e-9)
    assert cloud.up_axis == "z"
