"""Several real sweeps placed by their poses into one map, from Python."""

import numpy as np
import pointray
import pytest


def test_sweeps_with_poses_become_one_map_that_keeps_each_sweeps_sensor(ouster_sequence):
    sweeps = [ouster_sequence / "scan00.bin", ouster_sequence / "scan02.bin"]
    single = [pointray.read(sweep) for sweep in sweeps]
    cloud = pointray.read_sweeps(sweeps, ouster_sequence / "poses_kitti.txt")
    assert len(cloud) == sum(len(sweep) for sweep in single)
    assert cloud.ring is not None and cloud.up_axis == "z"
    origins = np.unique(cloud.sensor_origins, axis=0)
    assert len(origins) == 2, "one sensor origin a sweep"
    # Sweep 2's pose moves it about half a metre forward.
    assert 0.4 < np.linalg.norm(origins[1] - origins[0]) < 0.6
    patches = pointray.prep(cloud)
    assert len(patches) == len(cloud)


def test_a_poses_file_that_does_not_fit_is_refused_naming_it(ouster_sequence, tmp_path):
    poses = tmp_path / "poses.txt"
    poses.write_text("1 0 0 0 0 1 0 0 0 0 1\n")
    with pytest.raises(pointray.PointrayError, match="poses.txt"):
        pointray.read_sweeps([ouster_sequence / "scan00.bin"], poses)
