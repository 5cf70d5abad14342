"""Patches round-trip through the patch store that `pointray prep` writes."""

import numpy as np
import pointray
import pytest

from conftest import pointray_cli


def test_save_and_load_round_trip(bunny, tmp_path):
    patches = pointray.prep(pointray.read(bunny))
    patches.save(tmp_path / "bunny.patches")
    loaded = pointray.Patches.load(tmp_path / "bunny.patches")
    assert len(loaded) == len(patches)
    assert np.array_equal(loaded.centers, patches.centers)
    assert np.array_equal(loaded.normals, patches.normals)
    assert np.array_equal(loaded.radii, patches.radii)
    assert loaded.offset == patches.offset


def test_python_prep_makes_the_command_lines_store(bunny, tmp_path):
    pointray_cli("prep", bunny, "-o", "cli.patches", cwd=tmp_path)
    pointray.prep(pointray.read(bunny)).save(tmp_path / "python.patches")
    assert (tmp_path / "python.patches").read_bytes() == (tmp_path / "cli.patches").read_bytes()


def test_a_broken_store_is_refused_with_its_name(tmp_path):
    broken = tmp_path / "broken.patches"
    broken.write_bytes(b"not a patch store")
    with pytest.raises(pointray.PointrayError, match="broken.patches"):
        pointray.Patches.load(broken)
