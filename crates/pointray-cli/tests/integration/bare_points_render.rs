//! `pointray render POINTS` gives a framed, lit image of a bare PLY, LAS or KITTI file, and
//! `--turntable` orbits the camera around it.

use std::path::Path;

use glam::{DVec3, Vec3};

use crate::common::{pointray_in, write_grid_ply};
use pointray_test_support::data_file;

const SIZE: [&str; 4] = ["--width", "80", "--height", "60"];

/// Renders `points` in `dir` to `out.exr` with AOVs; returns the colour and instance pixels.
fn render(dir: &Path, points: &Path, extra: &[&str]) -> (Vec<Vec3>, Vec<f32>) {
    let mut args = vec!["render", points.to_str().unwrap(), "-o", "out.exr", "--backend", "cpu", "--aovs"];
    args.extend(SIZE);
    args.extend(extra);
    let (ok, stdout, stderr) = pointray_in(dir, &args);
    assert!(ok, "render failed: {stdout}{stderr}");
    let color = read_exr(&dir.join("out.exr"));
    let instance = read_exr(&dir.join("out.instance.exr")).iter().map(|p| p.x).collect();
    (color, instance)
}

fn read_exr(path: &Path) -> Vec<Vec3> {
    let image = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).into_rgb32f();
    image.pixels().map(|p| Vec3::from(p.0)).collect()
}

/// The cloud (object 0) covers a fair part of the image and lies inside it, and it is lit:
/// its pixels are neither black nor all one shade.
fn assert_framed_and_lit(name: &str, (color, instance): &(Vec<Vec3>, Vec<f32>)) {
    let cloud: Vec<usize> = (0..instance.len()).filter(|&i| instance[i] == 0.0).collect();
    let coverage = cloud.len() as f32 / instance.len() as f32;
    assert!(coverage > 0.05, "{name}: the cloud covers only {:.1}% of the image", 100.0 * coverage);
    let (width, height) = (80, 60);
    let touches_border = cloud
        .iter()
        .any(|&i| i % width == 0 || i % width == width - 1 || i / width == 0 || i / width == height - 1);
    assert!(!touches_border, "{name}: the cloud runs off the image; the framing should fit it");
    let brightness: Vec<f32> = cloud.iter().map(|&i| color[i].element_sum() / 3.0).collect();
    let mean = brightness.iter().sum::<f32>() / brightness.len() as f32;
    let spread = brightness.iter().fold(0.0f32, |m, &b| m.max((b - mean).abs()));
    assert!(mean > 0.05, "{name}: the cloud is dark (mean {mean})");
    assert!(spread > 0.02, "{name}: the cloud is flat, unlit (spread {spread})");
}

#[test]
fn a_bare_ply_renders_framed_and_lit_on_a_floor() {
    let dir = tempfile::tempdir().unwrap();
    let points = dir.path().join("grid.ply");
    write_grid_ply(&points);
    let image = render(dir.path(), &points, &[]);
    assert_framed_and_lit("grid.ply", &image);
    assert!(image.1.contains(&1.0), "the floor (object 1) is under the cloud");
    let without_floor = render(dir.path(), &points, &["--floor", "false"]);
    assert!(!without_floor.1.contains(&1.0), "--floor false leaves the floor out");
}

#[test]
fn a_kitti_sweep_stands_upright() {
    let dir = tempfile::tempdir().unwrap();
    let points = dir.path().join("sweep.bin");
    // A ground patch, Z up: x, y across, z a gentle wave, and an intensity per point.
    let mut bytes = Vec::new();
    for i in 0..1600 {
        let (x, y) = ((i % 40) as f32 * 0.25, (i / 40) as f32 * 0.25);
        for value in [x, y, 0.2 * (x * 0.7).sin(), (i % 7) as f32 / 7.0] {
            bytes.extend(value.to_le_bytes());
        }
    }
    std::fs::write(&points, bytes).unwrap();
    let image = render(dir.path(), &points, &[]);
    assert_framed_and_lit("sweep.bin", &image);
    // Stood upright, the ground is seen from above like the floor under it; taken as Y-up it
    // would stand on edge and hide the floor behind a wall.
    let on_edge = render(dir.path(), &points, &["--up-axis", "y"]);
    let cloud_pixels =
        |(_, instance): &(Vec<Vec3>, Vec<f32>)| instance.iter().filter(|&&id| id == 0.0).count();
    assert!(cloud_pixels(&image) != cloud_pixels(&on_edge), "--up-axis changes how the sweep stands");
}

#[test]
fn a_las_tile_renders_in_its_own_colours() {
    let tile = data_file("scans/autzen_trim.las");
    let dir = tempfile::tempdir().unwrap();
    let image = render(dir.path(), &tile, &[]);
    assert_framed_and_lit("autzen_trim.las", &image);
    let (color, instance) = &image;
    let tinted = (0..color.len())
        .filter(|&i| instance[i] == 0.0)
        .filter(|&i| color[i].max_element() - color[i].min_element() > 0.05)
        .count();
    assert!(tinted > 50, "the tile's RGB should show (auto colour source); {tinted} coloured pixels");
}

#[test]
fn a_turntable_orbits_the_cloud() {
    let dir = tempfile::tempdir().unwrap();
    let points = dir.path().join("grid.ply");
    write_grid_ply(&points);
    let mut args = vec!["render", "grid.ply", "-o", "spin.png", "--backend", "cpu", "--turntable", "8"];
    args.extend(SIZE);
    let (ok, stdout, stderr) = pointray_in(dir.path(), &args);
    assert!(ok, "{stdout}{stderr}");
    let cameras: Vec<DVec3> = stdout
        .lines()
        .filter_map(|line| line.split_once(": camera at ").map(|(_, at)| at))
        .map(|at| {
            let v: Vec<f64> = at.split(',').map(|c| c.parse().unwrap()).collect();
            DVec3::new(v[0], v[1], v[2])
        })
        .collect();
    assert_eq!(cameras.len(), 8, "{stdout}");
    for index in 0..8 {
        assert!(dir.path().join(format!("spin-{index:04}.png")).is_file(), "image {index} is written");
    }
    // The orbit is about the vertical through the look-at point: same height, same distance
    // from its axis, an eighth of a turn apart.
    let axis = cameras.iter().fold(DVec3::ZERO, |sum, c| sum + *c) / 8.0;
    let radius = |c: &DVec3| (DVec3::new(c.x, 0.0, c.z) - DVec3::new(axis.x, 0.0, axis.z)).length();
    for pair in cameras.windows(2) {
        assert!((pair[0].y - pair[1].y).abs() < 1e-4, "{cameras:?}");
        assert!((radius(&pair[0]) - radius(&pair[1])).abs() < 1e-4 * radius(&pair[0]), "{cameras:?}");
        let chord = (pair[0] - pair[1]).length();
        let expected = 2.0 * radius(&pair[0]) * (std::f64::consts::PI / 8.0).sin();
        assert!((chord - expected).abs() < 1e-3 * expected, "an eighth of a turn apart: {cameras:?}");
    }
}

#[test]
fn a_gpu_memory_budget_on_the_cpu_backend_is_named_as_unused() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    let mut args = vec!["render", "grid.ply", "-o", "out.png", "--backend", "cpu", "--gpu-memory", "1G"];
    args.extend(SIZE);
    let (ok, stdout, stderr) = pointray_in(dir.path(), &args);
    assert!(ok, "{stdout}{stderr}");
    assert!(stderr.contains("--gpu-memory budgets the Vulkan backend"), "{stderr}");
    let bad = ["render", "grid.ply", "-o", "bad.png", "--backend", "cpu", "--gpu-memory", "lots"];
    let (ok, _, stderr) = pointray_in(dir.path(), &bad);
    assert!(!ok && stderr.contains("'lots' is not a memory size"), "{stderr}");
}
