"""The Airborne LAS tile written here as COPC by copclib, a library that writes COPC, reads as
pointray reads the LAS, up to point order, and prep streams it along its octree to the LAS's
patches, up to point order and the rounding of another recentring."""

import importlib.util

import numpy as np
import pointray

from conftest import REPOSITORY, pointray_cli

# Patch centres are compared on grids of this step (feet), the second shifted by half a step:
# the recentring moves a centre by far less than a quarter step, so it keeps its cell in one
# of the two; a point lost or moved would move thousands.
CENTRE_STEP = 0.01


def copc_writer():
    path = REPOSITORY / "data" / "scans" / "write_autzen_copc.py"
    spec = importlib.util.spec_from_file_location("write_autzen_copc", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def rows_in_order(values):
    return values[np.lexsort(values.T[::-1])]


def cells(centres, shift):
    return [tuple(cell) for cell in np.floor(centres / CENTRE_STEP + shift).astype(np.int64)]


def shared_centres(a, b):
    """How many of centres `a` lie in a cell of one of the two grids that centres `b` hold."""
    grids = [(cells(a, shift), set(cells(b, shift))) for shift in (0.0, 0.5)]
    return sum(any(cells_a[i] in held for cells_a, held in grids) for i in range(len(a)))


def test_copc_written_by_copclib_reads_and_preps_as_its_las(autzen, tmp_path):
    copc = tmp_path / "autzen.copc.laz"
    assert copc_writer().write_copc(autzen, copc) > 8
    from_las, from_copc = pointray.read(autzen), pointray.read(copc)
    assert len(from_copc) == len(from_las)
    assert np.array_equal(rows_in_order(from_copc.positions), rows_in_order(from_las.positions))

    for source, store in [(copc, "copc.patches"), (autzen, "las.patches")]:
        pointray_cli("prep", source, "-o", store, "--tiles", "4", "--memory", "1G", cwd=tmp_path)
    las, copc = (pointray.Patches.load(tmp_path / name) for name in ["las.patches", "copc.patches"])
    assert len(copc) == len(las)
    shared = shared_centres(copc.centers, las.centers)
    assert shared >= 0.999 * len(las), f"{shared} of {len(las)} patch centres shared"
