"""Prep as tile jobs: `prep_tile` and `merge_tiles` write the command line's tile files and
store, and `dask_prep` fanned out over worker processes writes the store of one process."""

import pointray
import pytest

from conftest import pointray_cli


def test_tile_jobs_merge_to_the_command_lines_store(bunny, tmp_path):
    pointray_cli("prep", bunny, "--tiles", "3", "--k", "12", "-o", "cli.patches", cwd=tmp_path)
    tiles = [tmp_path / f"{index}.tile" for index in range(3)]
    owned = [pointray.prep_tile(bunny, index, 3, path, k=12) for index, path in enumerate(tiles)]
    assert sum(owned) == 35947
    patches = pointray.merge_tiles(reversed(tiles), tmp_path / "python.patches")
    assert patches == len(pointray.Patches.load(tmp_path / "cli.patches"))
    assert (tmp_path / "python.patches").read_bytes() == (tmp_path / "cli.patches").read_bytes()
    assert pointray.merge_tiles(tiles, tmp_path / "removed.patches", remove_tiles=True) == patches
    assert (tmp_path / "removed.patches").read_bytes() == (tmp_path / "cli.patches").read_bytes()
    assert not any(path.exists() for path in tiles)


def test_tile_jobs_on_a_sort_the_command_line_kept_write_the_same_tiles(bunny, tmp_path):
    pointray_cli("prep", bunny, "--keep-sort", "--k", "12", "-o", "bunny.sorted", cwd=tmp_path)
    for index in range(3):
        from_input = tmp_path / f"input{index}.tile"
        from_sort = tmp_path / f"sorted{index}.tile"
        pointray.prep_tile(bunny, index, 3, from_input, k=12)
        pointray.prep_tile(tmp_path / "bunny.sorted", index, 3, from_sort, k=12)
        assert from_sort.read_bytes() == from_input.read_bytes()


def test_a_cut_missing_a_tile_or_naming_no_tile_is_refused(bunny, tmp_path):
    pointray.prep_tile(bunny, 0, 2, tmp_path / "0.tile")
    with pytest.raises(pointray.PointrayError, match="tile 1 of 2 is missing"):
        pointray.merge_tiles([tmp_path / "0.tile"], tmp_path / "out.patches")
    assert not (tmp_path / "out.patches").exists()
    with pytest.raises(pointray.PointrayError, match="tile 2 is not one of 2 tiles"):
        pointray.prep_tile(bunny, 2, 2, tmp_path / "2.tile")
    with pytest.raises(pointray.PointrayError, match="invalid setting `k`"):
        pointray.prep_tile(bunny, 1, 2, tmp_path / "1.tile", k=0)


def test_dask_prep_on_worker_processes_writes_the_store_of_one_process(bunny, tmp_path):
    from distributed import Client, LocalCluster

    pointray_cli("prep", bunny, "--tiles", "4", "-o", "cli.patches", cwd=tmp_path)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        patches = pointray.dask_prep(bunny, tmp_path / "dask.patches", tiles=4, client=client)
        assert len(client.scheduler_info()["workers"]) == 2
        # A job's failure reaches the caller as the command line's error, and leaves no tiles.
        with pytest.raises(pointray.PointrayError, match="missing.ply: file not found"):
            pointray.dask_prep(tmp_path / "missing.ply", tmp_path / "missing.patches", tiles=2, client=client)
    assert patches == len(pointray.Patches.load(tmp_path / "cli.patches"))
    assert (tmp_path / "dask.patches").read_bytes() == (tmp_path / "cli.patches").read_bytes()
    assert sorted(path.name for path in tmp_path.iterdir()) == ["cli.patches", "dask.patches"]


def test_dask_prep_without_a_client_says_what_it_needs(bunny, tmp_path):
    with pytest.raises(ValueError, match="needs a dask.distributed Client"):
        pointray.dask_prep(bunny, tmp_path / "out.patches", tiles=2)
