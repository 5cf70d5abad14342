//! Scene files become scenes: files resolve and are named when missing, transforms compose,
//! point sets come back to their input coordinates, grounds fit the other objects, and a
//! scene without a camera is framed.

use crate::common;

use std::path::Path;

use common::{assert_close, tetrahedron};
use glam::{DVec3, Vec3};
use pointray_scene::bounds::{center, diagonal, extent};
use pointray_scene::ground::AUTO_SIZE_FACTOR;
use pointray_scene::{Background, Geometry, LoadOptions, PointSetOrigin, Scene, SceneError, load_scene};

fn write_scene(dir: &Path, text: &str) -> std::path::PathBuf {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// `tet.ply` in `dir`: the tetrahedron on `corners`.
fn write_tetrahedron(dir: &Path, corners: [Vec3; 4]) {
    pointray_io::formats::ply::write_triangle_mesh(&dir.join("tet.ply"), &tetrahedron(corners)).unwrap();
}

fn world_points(scene: &Scene, object: usize) -> Vec<Vec3> {
    let object = &scene.objects[object];
    object.geometry.local_points().map(|p| object.transform.transform_point3(p)).collect()
}

#[test]
fn a_missing_file_is_named_with_the_scene_and_the_object() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "[[objects]]\ntype = \"mesh\"\npath = \"models/nope.ply\"\n");
    let error = load_scene(&scene, &LoadOptions::default()).unwrap_err();
    let message = error.to_string();
    assert!(matches!(error, SceneError::Input { .. }), "{error:?}");
    assert!(message.contains("file not found") && message.contains("scene.toml"), "{message}");
    assert!(message.contains("objects[0]"), "{message}");
    assert!(message.contains(&dir.path().join("models/nope.ply").display().to_string()), "{message}");
}

#[test]
fn a_folder_named_as_a_points_file_is_called_a_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("cloud.ply")).unwrap();
    let scene = write_scene(dir.path(), "[[objects]]\ntype = \"points\"\npath = \"cloud.ply\"\n");
    let message = load_scene(&scene, &LoadOptions::default()).unwrap_err().to_string();
    assert!(message.contains("cloud.ply: is a folder, not a file"), "{message}");
}

#[test]
fn the_scene_lists_every_file_it_reads() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(
        dir.path(),
        "[[objects]]\ntype = \"points\"\npath = \"a.ply\"\n[[objects]]\ntype = \"mesh\"\npath = \"m/b.obj\"\n\
         [[objects]]\ntype = \"ground\"\n",
    );
    let file = pointray_scene::SceneFile::read(&scene).unwrap();
    assert_eq!(file.input_files(), vec![scene.clone(), dir.path().join("a.ply"), dir.path().join("m/b.obj")]);
}

#[test]
fn an_environment_map_is_read_scaled_and_listed_among_the_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let texels: Vec<Vec3> = (0..32).map(|i| Vec3::new(i as f32, 1.0, 0.5)).collect();
    pointray_io::image_output::write_exr_linear(&dir.path().join("sky.exr"), 8, 4, &texels).unwrap();
    let scene = write_scene(
        dir.path(),
        "background = { map = \"sky.exr\", intensity = 2.0, rotation_degrees = 90.0 }\n",
    );
    let file = pointray_scene::SceneFile::read(&scene).unwrap();
    assert_eq!(file.input_files(), vec![scene.clone(), dir.path().join("sky.exr")]);
    let loaded = load_scene(&scene, &LoadOptions::default()).unwrap();
    let Background::Map(map) = &loaded.scene.background else {
        panic!("a map, not {:?}", loaded.scene.background)
    };
    assert_eq!((map.width(), map.height(), map.rotation()), (8, 4, 0.25));
    assert_eq!(map.texels()[5], [10.0, 2.0, 1.0, 0.0]);
}

#[test]
fn an_environment_map_that_cannot_serve_is_an_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "background = { map = \"missing.hdr\" }\n");
    let message = load_scene(&scene, &LoadOptions::default()).unwrap_err().to_string();
    assert!(message.contains("background.map") && message.contains("missing.hdr"), "{message}");
    pointray_io::image_output::write_exr_linear(&dir.path().join("wide.exr"), 3, 1, &[Vec3::ONE; 3]).unwrap();
    let scene = write_scene(dir.path(), "background = { map = \"wide.exr\" }\n");
    let message = load_scene(&scene, &LoadOptions::default()).unwrap_err().to_string();
    assert!(message.contains("wide.exr") && message.contains("twice as wide"), "{message}");
}

#[test]
fn a_sun_and_sky_needs_no_file_and_lights_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(
        dir.path(),
        "background = { sun_elevation_degrees = 30.0, sun_azimuth_degrees = 90.0 }\n",
    );
    let loaded = load_scene(&scene, &LoadOptions::default()).unwrap();
    let background = &loaded.scene.background;
    assert!(matches!(background, Background::Map(_)) && background.is_lit());
    // The sun lies toward +x, 30 degrees up, and outshines the sky beside it.
    let sun = Vec3::new(30f32.to_radians().cos(), 30f32.to_radians().sin(), 0.0);
    let beside = Vec3::new(0.0, 30f32.to_radians().sin(), 30f32.to_radians().cos());
    assert!(background.radiance(sun).y > 100.0 * background.radiance(beside).y);
}

#[test]
fn a_malformed_input_file_is_an_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("junk.ply"), b"ply\nformat nonsense\n").unwrap();
    let scene = write_scene(dir.path(), "[[objects]]\ntype = \"points\"\npath = \"junk.ply\"\n");
    let error = load_scene(&scene, &LoadOptions::default()).unwrap_err();
    assert!(matches!(error, SceneError::Input { .. }), "{error:?}");
    assert!(error.to_string().contains("junk.ply"), "{error}");
}

#[test]
fn transforms_scale_then_rotate_then_translate() {
    let dir = tempfile::tempdir().unwrap();
    let corners = [Vec3::X, Vec3::Y, Vec3::Z, Vec3::ZERO];
    write_tetrahedron(dir.path(), corners);
    let scene = write_scene(
        dir.path(),
        r#"
        [[objects]]
        type = "mesh"
        path = "tet.ply"
        [objects.transform]
        scale = 2.0
        rotate = [0.0, 0.0, 90.0]
        translate = [0.0, 0.0, 5.0]

        [[objects]]
        type = "mesh"
        path = "tet.ply"
        [objects.transform]
        rotate = { axis = [0.0, 0.0, 1.0], degrees = 90.0 }
        scale = [1.0, 3.0, 1.0]

        [[objects]]
        type = "mesh"
        path = "tet.ply"
        [objects.transform]
        rotate = [90.0, 90.0, 0.0]
        "#,
    );
    let scene = load_scene(&scene, &LoadOptions::default()).unwrap().scene;
    // X scaled to 2, turned 90 degrees about Z onto +Y, then moved up Z.
    assert_close(world_points(&scene, 0)[0], Vec3::new(0.0, 2.0, 5.0), 1e-5);
    // Scale Y by 3 first, then turn: Y (length 3) lands on -X.
    assert_close(world_points(&scene, 1)[1], Vec3::new(-3.0, 0.0, 0.0), 1e-5);
    // Euler angles apply about X first: Y -> Z, then about Y: Z -> X.
    assert_close(world_points(&scene, 2)[1], Vec3::X, 1e-5);
    assert_eq!(scene.objects[0].name, "tet");
}

#[test]
fn point_sets_return_to_their_input_coordinates() {
    let dir = tempfile::tempdir().unwrap();
    let center_in_file = DVec3::new(10.0, 20.0, 30.0);
    common::write_sphere_ply(&dir.path().join("ball.ply"), center_in_file, 2000);
    let scene = write_scene(
        dir.path(),
        r#"
        [[objects]]
        type = "points"
        path = "ball.ply"
        [[objects]]
        name = "moved"
        type = "points"
        path = "ball.ply"
        prep = { k = 12 }
        [objects.transform]
        translate = [1.0, 0.0, 0.0]
        "#,
    );
    let loaded = load_scene(&scene, &LoadOptions::default()).unwrap();
    let scene = loaded.scene;
    let bounds = scene.objects[0].world_bounds().unwrap();
    assert_close(center(&bounds), center_in_file.as_vec3(), 1e-3);
    assert_close(extent(&bounds), Vec3::splat(2.0), 1e-2);
    let moved = scene.objects[1].world_bounds().unwrap();
    assert_close(center(&moved), center_in_file.as_vec3() + Vec3::X, 1e-3);
    assert_eq!(scene.objects[1].name, "moved");
    let Geometry::Patches(patches) = &scene.objects[1].geometry else { panic!("a point set") };
    assert_eq!(patches.settings.k, 12, "the file's k reaches prep");
    assert_eq!(loaded.point_sets.len(), 2);
    assert!(loaded.point_sets.iter().all(|(_, origin)| *origin == PointSetOrigin::Prepped { cache: None }));
}

#[test]
fn an_auto_ground_sits_at_the_lowest_point_and_spans_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    let corners = [
        Vec3::new(1.0, -0.5, 0.0),
        Vec3::new(3.0, 1.0, 0.0),
        Vec3::new(2.0, 0.0, 2.0),
        Vec3::new(2.0, 2.0, 1.0),
    ];
    write_tetrahedron(dir.path(), corners);
    let scene = write_scene(
        dir.path(),
        r#"
        [[objects]]
        type = "ground"
        auto = true
        [[objects]]
        type = "mesh"
        path = "tet.ply"
        [objects.transform]
        translate = [0.0, 1.0, 0.0]
        [[objects]]
        type = "ground"
        height = -3.0
        size = 2.0
        "#,
    );
    let scene = load_scene(&scene, &LoadOptions::default()).unwrap().scene;
    let model = scene.objects[1].world_bounds().unwrap();
    let auto = scene.objects[0].world_bounds().unwrap();
    assert_eq!(auto.min[1], 0.5, "the lowest point after the translation");
    assert_eq!(auto.max[1], 0.5, "a flat ground");
    assert_close(center(&auto) * Vec3::new(1.0, 0.0, 1.0), center(&model) * Vec3::new(1.0, 0.0, 1.0), 1e-5);
    let size = extent(&auto).x;
    assert!((size - AUTO_SIZE_FACTOR * diagonal(&model)).abs() < 1e-4, "size {size}");
    assert_eq!(extent(&auto).z, size);
    let fixed = scene.objects[2].world_bounds().unwrap();
    assert_eq!((fixed.min[1], extent(&fixed).x), (-3.0, 2.0));
    let Geometry::Mesh(ground) = &scene.objects[0].geometry else { panic!("a ground is a mesh") };
    assert!(ground.face_normal(0).normalize().y > 0.999, "the ground faces up");
    assert_eq!(scene.objects[0].name, "ground", "object order is the file's order");
}

#[test]
fn scene_bounds_and_ray_epsilon_cover_every_object() {
    let dir = tempfile::tempdir().unwrap();
    let corners = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
    write_tetrahedron(dir.path(), corners);
    let scene = write_scene(
        dir.path(),
        "[[objects]]\ntype = \"mesh\"\npath = \"tet.ply\"\n[[objects]]\ntype = \"mesh\"\npath = \"tet.ply\"\n\
         [objects.transform]\ntranslate = [4.0, 0.0, 0.0]\n",
    );
    let scene = load_scene(&scene, &LoadOptions::default()).unwrap().scene;
    let bounds = scene.bounds().unwrap();
    assert_eq!((bounds.min, bounds.max), ([0.0; 3], [5.0, 1.0, 1.0]));
    let expected = 1e-4 * 27.0f32.sqrt();
    assert!((scene.ray_epsilon() - expected).abs() < 1e-9, "{}", scene.ray_epsilon());
}

#[test]
fn without_a_camera_the_objects_are_framed() {
    let dir = tempfile::tempdir().unwrap();
    let corners = [
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 3.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    ];
    write_tetrahedron(dir.path(), corners);
    let scene = write_scene(
        dir.path(),
        "[render]\nwidth = 200\nheight = 400\n[[objects]]\ntype = \"mesh\"\npath = \"tet.ply\"\n\
         [[objects]]\ntype = \"ground\"\nauto = true\n",
    );
    let loaded = load_scene(&scene, &LoadOptions::default()).unwrap();
    assert_eq!((loaded.settings.width, loaded.settings.height), (200, 400));
    let camera = loaded.scene.camera;
    let model = loaded.scene.objects[0].world_bounds().unwrap();
    assert_close(camera.look_at, center(&model), 1e-5);
    // Every vertex of the model projects inside the (tall, narrow) image.
    let forward = (camera.look_at - camera.position).normalize();
    let right = forward.cross(camera.up).normalize();
    let up = right.cross(forward);
    let tan_v = (camera.vertical_fov_degrees.to_radians() * 0.5).tan();
    let tan_h = tan_v * 200.0 / 400.0;
    for p in world_points(&loaded.scene, 0) {
        let d = p - camera.position;
        let depth = d.dot(forward);
        assert!(depth > 0.0);
        assert!(
            (d.dot(right) / depth).abs() <= tan_h && (d.dot(up) / depth).abs() <= tan_v,
            "{p} is outside"
        );
    }
}

#[test]
fn framing_camera_fits_the_bounds_sphere() {
    let bounds = pointray_scene::bounds::bounds_of_points([Vec3::splat(-1.0), Vec3::splat(1.0)]).unwrap();
    let camera = Scene::framing_camera(&bounds, Vec3::Z, 60.0, 1.0);
    // The sphere of radius sqrt(3) touches the 30 degree half angle: distance = r / sin(30).
    assert_close(camera.position, Vec3::new(0.0, 0.0, 2.0 * 3.0f32.sqrt()), 1e-5);
    assert_eq!(camera.up, Vec3::Y);
    let from_above = Scene::framing_camera(&bounds, Vec3::Y, 60.0, 1.0);
    assert!(from_above.up.cross(Vec3::Y).length() > 0.9, "up is not the view axis");
}

#[test]
fn the_demo_scene_needs_no_data_and_has_shadows_and_reflections() {
    let loaded = pointray_scene::load_demo(&LoadOptions::default()).unwrap();
    let scene = &loaded.scene;
    assert_eq!(scene.objects.len(), 3);
    assert_eq!(scene.lights.len(), 1);
    let patches: usize = scene
        .objects
        .iter()
        .map(|o| match &o.geometry {
            Geometry::Patches(p) => p.len(),
            Geometry::Mesh(_) => 0,
        })
        .sum();
    assert!((20_000..=60_000).contains(&patches), "{patches} patches");
    let ground = scene.objects.iter().find(|o| o.name == "ground").unwrap();
    assert!(ground.material.reflectivity > 0.0);
    assert!(loaded.point_sets.iter().all(|(_, origin)| *origin == PointSetOrigin::Procedural));
    // Both models stand on the ground: their lowest points are close to its height.
    let ground_height = ground.world_bounds().unwrap().min[1];
    for model in scene.objects.iter().filter(|o| o.name != "ground") {
        let lowest = model.world_bounds().unwrap().min[1];
        assert!((lowest - ground_height).abs() < 0.02, "{} floats: {lowest} vs {ground_height}", model.name);
    }
    assert_eq!((loaded.settings.width, loaded.settings.height), (640, 480));
}

#[test]
fn procedural_spheres_fit_their_analytic_surface() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(
        dir.path(),
        "[[objects]]\ntype = \"sphere_points\"\ncenter = [1.0, 2.0, 3.0]\nradius = 0.5\ncount = 3000\n",
    );
    let scene = load_scene(&scene, &LoadOptions::default()).unwrap().scene;
    let Geometry::Patches(patches) = &scene.objects[0].geometry else { panic!("a point set") };
    assert_eq!(patches.len(), 3000);
    for p in world_points(&scene, 0) {
        assert!(((p - Vec3::new(1.0, 2.0, 3.0)).length() - 0.5).abs() < 1e-4, "{p} is off the sphere");
    }
}

#[test]
fn the_example_scenes_load_with_the_checkouts_data() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let cache = tempfile::tempdir().unwrap();
    for name in ["bunny_mesh_floor.toml", "bunny_floor.toml"] {
        let file = pointray_scene::SceneFile::read(&scenes.join(name)).unwrap();
        let options = LoadOptions { cache_dir: Some(cache.path()), ..LoadOptions::default() };
        let scene = pointray_scene::load_scene_file(&file, &options).unwrap().scene;
        let bunny = scene.objects[0].world_bounds().unwrap();
        // SOURCES.md: the bunny's box is (-0.0947, 0.0330, -0.0619) .. (0.0610, 0.1873, 0.0588).
        assert_close(Vec3::from(bunny.min), Vec3::new(-0.094690, 0.032987, -0.061874), 1e-3);
        assert_close(Vec3::from(bunny.max), Vec3::new(0.061009, 0.187321, 0.058800), 1e-3);
        let floor = scene.objects[1].world_bounds().unwrap();
        assert!((floor.min[1] - bunny.min[1]).abs() < 1e-3, "{name}: the floor touches the bunny");
    }
}

#[test]
fn obj_meshes_load_like_ply_meshes() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("quad.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
    let scene = write_scene(dir.path(), "[[objects]]\ntype = \"mesh\"\npath = \"quad.obj\"\n");
    let scene = load_scene(&scene, &LoadOptions::default()).unwrap().scene;
    let Geometry::Mesh(mesh) = &scene.objects[0].geometry else { panic!("a mesh") };
    assert_eq!(mesh.triangles.len(), 2, "the quad is split in two");
    assert_eq!(scene.objects[0].name, "quad");
}

#[test]
fn a_bare_points_file_gets_a_framed_scene_on_a_ground() {
    let dir = tempfile::tempdir().unwrap();
    let points = dir.path().join("ball.ply");
    common::write_sphere_ply(&points, DVec3::new(0.0, 5.0, 0.0), 1000);
    let file = pointray_scene::SceneFile::for_points_file(&points);
    let loaded = pointray_scene::load_scene_file(&file, &LoadOptions::default()).unwrap();
    let scene = &loaded.scene;
    assert_eq!(scene.objects.len(), 2);
    assert_eq!(scene.lights.len(), 1);
    let ball = scene.objects[0].world_bounds().unwrap();
    assert_close(scene.camera.look_at, center(&ball), 1e-3);
    let ground = scene.objects[1].world_bounds().unwrap();
    assert!((ground.min[1] - ball.min[1]).abs() < 1e-6, "the ground is under the ball");
    assert!(scene.objects[1].material.reflectivity > 0.0);
}
