"""Images from Python are the command line's images, bit for bit."""

import numpy as np
import pointray
import pytest

from conftest import pointray_cli

SIZE = dict(width=96, height=72)


def test_a_points_file_renders_as_the_command_line_renders_it(bunny, tmp_path):
    pointray_cli("render", bunny, "-o", "cli.exr", "--backend", "cpu", "--width", 96, "--height", 72, cwd=tmp_path)
    image = pointray.render(bunny, backend="cpu", **SIZE)
    assert image.shape == (72, 96, 4) and image.dtype == np.float32
    image.save(tmp_path / "python.exr")
    assert (tmp_path / "python.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()


def test_a_scene_built_in_python_renders_as_its_scene_file(bunny, tmp_path):
    scene = (pointray.Scene()
             .light("point", position=[0.3, 0.5, 0.4])
             .background([0.2, 0.2, 0.25])
             .points(bunny, material={"diffuse": [0.9, 0.5, 0.3], "reflectivity": 0.1})
             .ground(auto=True)
             .render_settings(width=80, height=60))
    (tmp_path / "scene.toml").write_text(scene.to_toml())
    pointray_cli("render", "scene.toml", "-o", "cli.exr", "--backend", "cpu", cwd=tmp_path)
    image = pointray.render(scene, backend="cpu")
    image.save(tmp_path / "python.exr")
    assert (tmp_path / "python.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
    again = pointray.Scene.from_file(tmp_path / "scene.toml")
    assert np.array_equal(pointray.render(again, backend="cpu"), image)


def test_points_in_memory_render_like_their_file(bunny):
    from_file = pointray.render(bunny, backend="cpu", **SIZE)
    from_cloud = pointray.render(pointray.read(bunny), backend="cpu", **SIZE)
    from_array = pointray.render(pointray.read(bunny).positions, backend="cpu", **SIZE)
    assert np.array_equal(from_file, from_cloud)
    assert np.array_equal(from_file, from_array)


def test_alpha_and_aovs_say_where_the_scene_was_hit(bunny):
    image = pointray.render(bunny, backend="cpu", aovs=True, floor=False, **SIZE)
    hit = image[..., 3] == 1.0
    assert 0.05 < hit.mean() < 0.95, "the bunny covers part of the frame"
    assert set(image.aovs) == {"depth", "normal", "instance", "primitive"}
    assert np.array_equal(hit, image.aovs["instance"] >= 0)
    assert np.isinf(image.aovs["depth"][~hit]).all() and np.isfinite(image.aovs["depth"][hit]).all()
    assert pointray.render(bunny, backend="cpu", **SIZE).aovs is None


def test_the_path_integrator_renders_as_the_command_line_renders_it(bunny, tmp_path):
    flags = ["--integrator", "path", "--spp", "4", "--max-depth", "3", "--seed", "5"]
    pointray_cli("render", bunny, "-o", "cli.exr", "--backend", "cpu", "--width", 96, "--height", 72, *flags,
                 cwd=tmp_path)
    path = dict(integrator="path", spp=4, max_depth=3, seed=5)
    image = pointray.render(bunny, backend="cpu", aovs=True, **path, **SIZE)
    image.save(tmp_path / "python.exr")
    assert (tmp_path / "python.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
    assert not np.array_equal(pointray.render(bunny, backend="cpu", **{**path, "seed": 6}, **SIZE), image)
    assert not np.array_equal(pointray.render(bunny, backend="cpu", **SIZE), image)
    albedo = image.aovs["albedo"]
    assert albedo.shape == (72, 96, 3) and (albedo[image[..., 3] == 1.0] > 0).any()
    assert "albedo" not in pointray.render(bunny, backend="cpu", aovs=True, **SIZE).aovs
    with pytest.raises(ValueError, match="whitted"):
        pointray.render(bunny, backend="cpu", integrator="photon")


def test_a_notebook_shows_the_png_the_command_line_writes(bunny, tmp_path):
    pointray_cli("render", bunny, "-o", "cli.png", "--backend", "cpu", "--width", 96, "--height", 72, cwd=tmp_path)
    image = pointray.render(bunny, backend="cpu", **SIZE)
    assert image._repr_png_() == (tmp_path / "cli.png").read_bytes()


def test_bad_render_settings_are_refused_with_the_command_lines_words(bunny):
    with pytest.raises(ValueError, match="width"):
        pointray.render(bunny, backend="cpu", width=0, height=10)
    with pytest.raises(ValueError, match="unknown backend"):
        pointray.render(bunny, backend="gpu")
    with pytest.raises(ValueError, match="'lots' is not a memory size"):
        pointray.render(bunny, backend="cpu", gpu_memory="lots")
    with pytest.raises(ValueError, match="gpu_memory: 0 bytes"):
        pointray.render(bunny, backend="cpu", gpu_memory=0)
    with pytest.raises(pointray.PointrayError, match="missing.ply"):
        pointray.render("missing.ply", backend="cpu")
    with pytest.raises(pointray.PointrayError, match="unknown field"):
        pointray.Scene.from_toml("[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nzoom = 2\n")


def test_a_camera_in_a_scans_coordinates_is_placed_as_the_command_line_places_it(autzen, tmp_path):
    centre = pointray.read(autzen).offset
    look_from = centre + [0.0, -900.0, 700.0]  # south of the tile and above it, Z up
    as_flag = lambda point: ",".join(f"{c:.3f}" for c in point)
    pointray_cli("render", autzen, "-o", "cli.exr", "--backend", "cpu", "--width", 96, "--height", 72,
                 "--look-from", as_flag(look_from), "--look-at", as_flag(centre), cwd=tmp_path)
    camera = dict(position=[float(f"{c:.3f}") for c in look_from], look_at=[float(f"{c:.3f}") for c in centre])
    image = pointray.render(autzen, backend="cpu", camera=camera, **SIZE)
    image.save(tmp_path / "python.exr")
    assert (tmp_path / "python.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
    assert (image[..., 3] == 1.0).mean() > 0.2, "the tile is in view"


def test_a_cameras_up_in_a_scans_coordinates_turns_the_image_as_the_command_lines_up_does(autzen, tmp_path):
    centre = pointray.read(autzen).offset
    look_from = centre + [0.0, -900.0, 700.0]
    rolled_up = [0.5, 0.0, 1.0]  # the file's Z up, leaning east: stood upright, the image rolls
    as_flag = lambda point: ",".join(f"{c:.3f}" for c in point)
    pointray_cli("render", autzen, "-o", "cli.exr", "--backend", "cpu", "--width", 96, "--height", 72,
                 "--look-from", as_flag(look_from), "--look-at", as_flag(centre), "--up", as_flag(rolled_up),
                 cwd=tmp_path)
    camera = dict(position=[float(f"{c:.3f}") for c in look_from], look_at=[float(f"{c:.3f}") for c in centre])
    rolled = pointray.render(autzen, backend="cpu", camera=dict(camera, up=rolled_up), **SIZE)
    rolled.save(tmp_path / "python.exr")
    assert (tmp_path / "python.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
    upright = pointray.render(autzen, backend="cpu", camera=camera, **SIZE)
    assert np.array_equal(pointray.render(autzen, backend="cpu", camera=dict(camera, up=[0, 0, 1]), **SIZE), upright), \
        "the file's Z is the default up"
    assert not np.array_equal(rolled, upright), "the up given rolls the image"


def test_a_sun_and_sky_lights_a_path_traced_scene_as_the_command_line_does(bunny, tmp_path):
    scene = (pointray.Scene()
             .background(sun_elevation_degrees=40.0, sun_azimuth_degrees=100.0)
             .points(bunny, material={"diffuse": [0.8, 0.8, 0.8]})
             .ground(auto=True)
             .render_settings(width=48, height=32, spp=2, max_depth=3, integrator="path"))
    (tmp_path / "scene.toml").write_text(scene.to_toml())
    pointray_cli("render", "scene.toml", "-o", "cli.exr", "--backend", "cpu", cwd=tmp_path)
    image = pointray.render(scene, backend="cpu")
    image.save(tmp_path / "python.exr")
    assert (tmp_path / "python.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
    assert np.asarray(image).max() > 0.1
    with pytest.raises(pointray.PointrayError, match="sun_elevation_degrees"):
        pointray.Scene().background(sun_elevation_degrees=120.0).to_toml()
    with pytest.raises(pointray.PointrayError, match="missing.exr"):
        pointray.render(pointray.Scene().background(map=tmp_path / "missing.exr"), backend="cpu")


def test_denoise_filters_as_the_command_line_does(bunny, tmp_path):
    scene = (pointray.Scene()
             .points(bunny, material={"diffuse": [0.8, 0.8, 0.8]})
             .ground(auto=True)
             .render_settings(width=48, height=32, spp=2, max_depth=3, integrator="path"))
    (tmp_path / "scene.toml").write_text(scene.to_toml())
    pointray_cli("render", "scene.toml", "-o", "cli.exr", "--backend", "cpu", "--denoise", cwd=tmp_path)
    image = pointray.render(scene, backend="cpu", denoise=True)
    image.save(tmp_path / "python.exr")
    assert (tmp_path / "python.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
    assert not np.array_equal(image, pointray.render(scene, backend="cpu"))


def test_a_render_over_its_gpu_budget_streams_and_warns_of_the_tiles_it_draws_coarse(bunny):
    # In boxes of one patch: in boxes of 4, which it would take where left to choose, it fits.
    with pytest.warns(UserWarning, match="are drawn from their coarse level"):
        image = pointray.render(bunny, width=48, height=48, backend="vulkan", gpu_memory="2M", patches_per_box=1)
    assert image.shape == (48, 48, 4) and image[..., 3].any()


def test_boxes_of_several_patches_render_the_patches_one_a_box_renders(bunny):
    # Both with packed records, which boxes of several patches read.
    one = pointray.render(bunny, width=48, height=48, backend="vulkan", aovs=True, patches_per_box=1,
                          hot_records="packed")
    fours = pointray.render(bunny, width=48, height=48, backend="vulkan", aovs=True, patches_per_box=4)
    assert np.array_equal(one.aovs["primitive"], fours.aovs["primitive"])
    assert np.abs(np.asarray(one) - np.asarray(fours)).max() < 1e-5
    with pytest.raises(ValueError, match="patches_per_box: must be between 1 and 64"):
        pointray.render(bunny, backend="vulkan", patches_per_box=0)


def test_unpacked_hot_records_render_the_packed_ones_picture(bunny):
    packed = pointray.render(bunny, width=48, height=48, backend="vulkan", aovs=True, hot_records="packed")
    unpacked = pointray.render(bunny, width=48, height=48, backend="vulkan", aovs=True, hot_records="unpacked")
    # Decoded on the host, the frames round otherwise: where overlapping patches all but tie,
    # a pixel may take the other one.
    assert (packed.aovs["primitive"] != unpacked.aovs["primitive"]).mean() <= 0.01
    assert np.abs(np.asarray(packed) - np.asarray(unpacked)).max() < 0.02
    with pytest.raises(ValueError, match="hot_records: unknown hot records"):
        pointray.render(bunny, backend="vulkan", hot_records="compressed")
    with pytest.raises(Exception, match="unpacked hot records need boxes of one patch"):
        pointray.render(bunny, backend="vulkan", hot_records="unpacked", patches_per_box=4)
