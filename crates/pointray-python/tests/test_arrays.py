"""numpy in: every dtype the API takes, and clear errors for what it does not."""

import numpy as np
import pointray
import pytest


def sheet(count: int = 900) -> np.ndarray:
    side = int(np.sqrt(count))
    x, z = np.meshgrid(np.arange(side), np.arange(side))
    return np.stack([x.ravel(), 0.1 * np.sin(x.ravel() * 0.5), z.ravel()], axis=1).astype(np.float64)


@pytest.mark.parametrize("dtype", [np.float64, np.float32, np.int32, np.int64, np.uint16])
def test_positions_of_any_numeric_dtype_prep_alike(dtype):
    positions = np.round(sheet() * 4)
    reference = pointray.prep(positions.astype(np.float64), scan="off")
    patches = pointray.prep(positions.astype(dtype), scan="off")
    assert len(patches) == len(reference) == len(positions)
    assert np.array_equal(patches.centers, reference.centers)
    assert np.array_equal(patches.normals, reference.normals)


def test_non_contiguous_and_list_input_are_taken():
    positions = sheet()
    strided = np.asfortranarray(positions)
    assert np.array_equal(pointray.prep(strided).centers, pointray.prep(positions).centers)
    assert len(pointray.prep(positions.tolist())) == len(positions)


def test_wrong_shapes_kinds_nan_and_empty_arrays_are_refused_clearly():
    with pytest.raises(ValueError, match=r"positions: expected an array of shape \(N, 3\), got \[10, 2\]"):
        pointray.prep(np.zeros((10, 2)))
    with pytest.raises(TypeError, match="positions: expected a float or integer array"):
        pointray.prep(np.array([["a", "b", "c"]]))
    nan = sheet()
    nan[17, 1] = np.nan
    with pytest.raises(pointray.PointrayError, match="point 17 has a coordinate that is NaN or infinite"):
        pointray.prep(nan)
    with pytest.raises(pointray.PointrayError, match="0 points"):
        pointray.prep(np.zeros((0, 3)))
    with pytest.raises(ValueError, match="colors has 3 values for 900 points"):
        pointray.prep(sheet(), colors=np.zeros((3, 3), dtype=np.uint8))
    with pytest.raises(ValueError, match="classification: 300 is not an integer in 0..256"):
        pointray.prep(sheet(), classification=np.full(900, 300))


def test_prep_settings_are_the_flags_and_checked_like_them():
    with pytest.raises(pointray.PointrayError, match="`k`: must be between 3 and 1024, got 1"):
        pointray.prep(sheet(), k=1)
    with pytest.raises(pointray.PointrayError, match="unknown variant `huge`"):
        pointray.prep(sheet(), radius="huge")
    with pytest.raises(pointray.PointrayError, match="unknown field `kk`"):
        pointray.prep(sheet(), kk=3)
    paper = pointray.prep(sheet(), radius="paper", boxes="cube", remove_outliers={"neighbors": 8, "sigmas": 2.0})
    cell = pointray.prep(sheet())
    assert not np.array_equal(paper.radii, cell.radii), "the radius setting reaches prep"


def test_a_clouds_offset_is_the_one_prep_recentres_on_whatever_a_stray_point(bunny):
    cloud = pointray.read(bunny)
    stray = np.vstack([cloud.positions, [[1e4, 0.0, 0.0]]])
    offset = pointray.PointCloud(positions=stray).offset
    assert np.array_equal(offset, pointray.prep(stray).offset)
    assert np.abs(offset - cloud.offset).max() < 0.01, "one far point leaves the centre in the bunny"


def test_the_extensions_arguments_are_typed_and_checked_when_made(bunny):
    from pointray import _native

    with pytest.raises(ValueError, match=r"normals: expected an array of shape \(N, 3\)"):
        _native.PointAttributes(normals=np.zeros((4, 2)))
    with pytest.raises(ValueError, match="sensor_position .* is not finite"):
        _native.PointAttributes(sensor_position=(0.0, float("nan"), 0.0))
    with pytest.raises(TypeError):
        _native.prep(sheet(), {"colors": None}, _native.PrepOptions())
    with pytest.raises(ValueError, match="unknown up axis `w`"):
        _native.RenderSource.points(points_file=str(bunny), up="w")
    with pytest.raises(pointray.PointrayError, match="unknown field"):
        _native.RenderSource.scene("[camera]\nzoom = 2\n", "scene.toml", [])
    with pytest.raises(ValueError, match="spp"):
        _native.ImageSettings(spp=0)
    with pytest.raises(TypeError):
        _native.render({"points_file": str(bunny)}, _native.RenderOptions(_native.ImageSettings()))
    with pytest.raises(ValueError, match="unknown up axis `w`"):
        pointray.render(bunny, backend="cpu", width=8, height=6, up="w")
