//! `color_source = "classification"` and `"height"`: colours computed at load into the
//! patches' cold records (where both renderers read point colours), and the clear errors for
//! objects that cannot give them; `columns` for headerless points files.

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use pointray_io::PointCloud;
use pointray_patches::PatchSet;
use pointray_scene::classification_palette::classification_color;
use pointray_scene::color_ramp::ColorRamp;
use pointray_scene::{Geometry, LoadOptions, SceneFile, SceneObject, load_scene, load_scene_file};

/// A 40x40 grid over [-1, 1]² in z = 0.5 x (a slope), ground (2) left of x = 0 and
/// buildings (6) right of it.
fn slope(with_classes: bool) -> PointCloud {
    let positions: Vec<DVec3> = (0..1600)
        .map(|i| {
            let (x, y) = (-1.0 + 0.05 * (i % 40) as f64, -1.0 + 0.05 * (i / 40) as f64);
            DVec3::new(x, y, 0.5 * x)
        })
        .collect();
    let classifications =
        with_classes.then(|| positions.iter().map(|p| if p.x < 0.0 { 2 } else { 6 }).collect());
    PointCloud { positions, classifications, ..PointCloud::default() }
}

fn write_points(dir: &Path, name: &str, cloud: &PointCloud) -> PathBuf {
    let path = dir.join(name);
    pointray_io::formats::ply::write_point_cloud(&path, cloud).unwrap();
    path
}

/// A scene of one points object with `extra` lines after its path (transform, material).
fn write_scene(dir: &Path, points: &Path, extra: &str) -> PathBuf {
    let text = format!("[[objects]]\ntype = \"points\"\npath = \"{}\"\n{extra}\n", points.display());
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn load_error(scene: &Path) -> String {
    load_scene(scene, &LoadOptions::default()).expect_err("the scene must be refused").to_string()
}

/// Cold records store linear RGB; the palette is sRGB.
fn linear(srgb: [u8; 3]) -> [u8; 3] {
    srgb.map(|c| {
        let c = f64::from(c) / 255.0;
        let linear = if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
        (linear * 255.0).round() as u8
    })
}

fn patches(object: &SceneObject) -> &PatchSet {
    match &object.geometry {
        Geometry::Patches(patches) => patches,
        Geometry::Mesh(_) => panic!("a point set was expected"),
    }
}

#[test]
fn classification_colours_each_patch_in_the_asprs_palette() {
    let dir = tempfile::tempdir().unwrap();
    let points = write_points(dir.path(), "classes.ply", &slope(true));
    let scene = write_scene(dir.path(), &points, "[objects.material]\ncolor_source = \"classification\"");
    let loaded = load_scene(&scene, &LoadOptions::default()).unwrap();
    let object = &loaded.scene.objects[0];
    assert!(object.material.use_point_colors);
    let patches = patches(object);
    let (ground, building) = (linear(classification_color(2)), linear(classification_color(6)));
    for (hot, cold) in patches.hot.iter().zip(&patches.cold) {
        let x = f64::from(hot.origin().x) + patches.offset.x;
        let rgb: [u8; 3] = cold.color_rgba8.to_le_bytes()[..3].try_into().unwrap();
        // A point on the border, x = 0, may be stored a quantisation step either side of it.
        let expected: &[[u8; 3]] = match x {
            x if x.abs() < 1e-5 => &[ground, building],
            x if x < 0.0 => &[ground],
            _ => &[building],
        };
        assert!(expected.contains(&rgb), "patch at x = {x}: {rgb:?}");
    }
}

#[test]
fn classification_without_classes_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let points = write_points(dir.path(), "plain.ply", &slope(false));
    let scene = write_scene(dir.path(), &points, "[objects.material]\ncolor_source = \"classification\"");
    let error = load_error(&scene);
    assert!(error.contains("plain.ply") && error.contains("no classification"), "{error}");
    assert!(error.contains("scene.toml") && error.contains("material.color_source"), "{error}");
}

#[test]
fn height_runs_the_ramp_from_the_lowest_to_the_highest_point_in_the_world() {
    let dir = tempfile::tempdir().unwrap();
    let points = write_points(dir.path(), "slope.ply", &slope(false));
    // The file's z (the slope) becomes the world's Y; geo-sized offsets must not matter.
    let extra = "[objects.transform]\nrotate = [-90.0, 0.0, 0.0]\ntranslate = [500000.0, 20.0, 0.0]\n\
                 [objects.material]\ncolor_source = \"height\"\nramp = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]";
    let scene = write_scene(dir.path(), &points, extra);
    let loaded = load_scene(&scene, &LoadOptions::default()).unwrap();
    let patches = patches(&loaded.scene.objects[0]);
    for (hot, cold) in patches.hot.iter().zip(&patches.cold) {
        let x = f64::from(hot.origin().x) + patches.offset.x;
        // z = 0.5 x runs from -0.5 to 0.475: the fraction of the way up is (x + 1) / 1.95.
        let up = ((x + 1.0) / 1.95) as f32;
        let color = cold.color();
        assert!((color.z - up).abs() < 0.01 && (color.x - (1.0 - up)).abs() < 0.01, "x = {x}: {color}");
    }
}

#[test]
fn height_defaults_to_viridis_and_works_on_procedural_points() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("sphere.toml");
    let text = "[[objects]]\ntype = \"sphere_points\"\nradius = 1.0\ncount = 2000\n\
                [objects.material]\ncolor_source = \"height\"";
    std::fs::write(&scene, text).unwrap();
    let loaded = load_scene(&scene, &LoadOptions::default()).unwrap();
    let patches = patches(&loaded.scene.objects[0]);
    let viridis = ColorRamp::named("viridis").unwrap();
    let (lowest, highest) = extremes(patches);
    assert!((patches.cold[lowest].color() - viridis.color_at(0.0)).length() < 0.01);
    assert!((patches.cold[highest].color() - viridis.color_at(1.0)).length() < 0.01);
}

fn extremes(patches: &PatchSet) -> (usize, usize) {
    let y = |i: usize| patches.hot[i].origin().y;
    let order = |a: &usize, b: &usize| y(*a).total_cmp(&y(*b));
    ((0..patches.len()).min_by(order).unwrap(), (0..patches.len()).max_by(order).unwrap())
}

#[test]
fn colour_sources_an_object_cannot_give_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("tri.ply");
    let triangle = pointray_io::TriangleMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        triangles: vec![[0, 1, 2]],
    };
    pointray_io::formats::ply::write_triangle_mesh(&mesh, &triangle).unwrap();
    let cases = [
        (format!("type = \"mesh\"\npath = \"{}\"", mesh.display()), "height", "applies to point sets"),
        ("type = \"ground\"".to_string(), "classification", "applies to point sets"),
        (
            "type = \"torus_points\"\nmajor_radius = 1.0\nminor_radius = 0.3\ncount = 500".to_string(),
            "classification",
            "has no classification",
        ),
    ];
    for (object, source, expected) in cases {
        let scene = dir.path().join("refused.toml");
        std::fs::write(
            &scene,
            format!("[[objects]]\n{object}\n[objects.material]\ncolor_source = \"{source}\"\n"),
        )
        .unwrap();
        let error = load_error(&scene);
        assert!(error.contains(expected) && error.contains("color_source"), "{source}: {error}");
    }
    let scene = write_scene(
        dir.path(),
        &write_points(dir.path(), "p.ply", &slope(true)),
        "[objects.material]\ncolor_source = \"points\"\nramp = \"grey\"",
    );
    assert!(load_error(&scene).contains("applies only with `color_source = \"intensity\"` or `\"height\"`"));
    let scene = write_scene(
        dir.path(),
        &dir.path().join("p.ply"),
        "[objects.material]\ncolor_source = \"height\"\nintensity_range = [0.0, 0.5]",
    );
    assert!(load_error(&scene).contains("intensity_range"));
}

#[test]
fn a_patch_store_has_no_classifications_to_colour_by() {
    let dir = tempfile::tempdir().unwrap();
    let (patches, _) =
        pointray_surface::prep(&slope(true), &Default::default(), &pointray_surface::NoProgress).unwrap();
    let store = dir.path().join("slope.patches");
    pointray_patches::patch_store::write(&store, &patches).unwrap();
    let scene = write_scene(dir.path(), &store, "[objects.material]\ncolor_source = \"classification\"");
    let error = load_error(&scene);
    assert!(error.contains("is a patch store") && error.contains("classification"), "{error}");
}

/// A 5-float sweep under a plain `.bin` name: refused as KITTI, read with `columns`.
#[test]
fn columns_read_a_headerless_file_the_name_does_not_explain() {
    let dir = tempfile::tempdir().unwrap();
    let points = dir.path().join("sweep.bin");
    let bytes: Vec<u8> = slope(false)
        .positions
        .iter()
        .enumerate()
        .flat_map(|(i, p)| [p.x as f32, p.y as f32, p.z as f32 - 1.8, 0.5, (i % 32) as f32])
        .flat_map(f32::to_le_bytes)
        .collect();
    std::fs::write(&points, bytes).unwrap();
    let error = load_error(&write_scene(dir.path(), &points, ""));
    assert!(error.contains("sweep.bin") && error.contains("does not read as KITTI"), "{error}");

    let scene = write_scene(dir.path(), &points, "columns = \"x,y,z,intensity,ring\"");
    let loaded = load_scene(&scene, &LoadOptions::default()).unwrap();
    assert_eq!(patches(&loaded.scene.objects[0]).len(), 1600);

    // The command line's columns reach every points object that names none.
    let file = SceneFile::for_points_file(&points).with_columns(Some(&"x y z i ring".parse().unwrap()));
    assert!(load_scene_file(&file, &LoadOptions::default()).is_ok());
    let scene = write_scene(dir.path(), &points, "columns = \"x,y,q\"");
    assert!(load_error(&scene).contains("unknown column name \"q\""));
}

#[test]
fn a_ramp_over_a_store_recolours_its_patches_and_leaves_the_file_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let (store, _) =
        pointray_surface::prep(&slope(false), &Default::default(), &pointray_surface::NoProgress).unwrap();
    let store_path = dir.path().join("slope.patches");
    pointray_patches::patch_store::write(&store_path, &store).unwrap();
    let before = std::fs::read(&store_path).unwrap();
    let scene = write_scene(dir.path(), &store_path, "[objects.material]\ncolor_source = \"height\"");
    let loaded = load_scene(&scene, &LoadOptions::default()).unwrap();
    let patches = patches(&loaded.scene.objects[0]);
    assert_ne!(patches.cold, store.cold, "the ramp coloured the patches");
    assert_eq!(std::fs::read(&store_path).unwrap(), before, "the store on disk is unchanged");
}

/// Intensities that are all 0 are stored as none (prep stores 0 for a point without one), so
/// the refusal of `color_source = "intensity"` says both, not "no intensity" alone.
#[test]
fn all_zero_intensities_are_named_as_such_when_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cloud = PointCloud { intensities: Some(vec![0.0; 1600]), ..slope(false) };
    let scene = write_scene(
        dir.path(),
        &write_points(dir.path(), "zeros.ply", &cloud),
        "[objects.material]\ncolor_source = \"intensity\"",
    );
    let error = load_error(&scene);
    assert!(error.contains("zeros.ply") && error.contains("every intensity is 0"), "{error}");
}
