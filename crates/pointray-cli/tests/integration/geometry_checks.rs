//! Geometry no renderer can build on is refused with a clear error before any BVH build:
//! patch stores that pass their checksum but hold NaN or 1e38 boxes or a NaN offset, cache
//! entries like them (which are regenerated, not kept), procedural objects and transforms
//! beyond the f32 range, and clouds too small to resolve.

use std::path::{Path, PathBuf};

use pointray_patches::patch_store;

use crate::common::{cached_store, pointray_in, write_grid_ply, write_points_scene};

fn render(dir: &Path, scene: &str) -> (bool, String) {
    let (ok, _, stderr) = pointray_in(
        dir,
        &["render", scene, "-o", "out.png", "--backend", "cpu", "--width", "24", "--height", "24"],
    );
    assert!(!stderr.contains("panicked"), "render panicked: {stderr}");
    (ok, stderr)
}

/// `grid.patches` in `dir`, prepped from a grid.
fn grid_store(dir: &Path) -> PathBuf {
    write_grid_ply(&dir.join("grid.ply"));
    let (ok, _, stderr) = pointray_in(dir, &["prep", "grid.ply", "-o", "grid.patches"]);
    assert!(ok, "{stderr}");
    dir.join("grid.patches")
}

/// Where section `i` of a store begins (0: the block frames, 1: the patches).
fn section(bytes: &[u8], i: usize) -> usize {
    u64::from_le_bytes(bytes[72 + 16 * i..80 + 16 * i].try_into().unwrap()) as usize
}

/// A NaN where a block's box begins.
fn nan_block_box(bytes: &mut [u8]) {
    let at = section(bytes, 0) + 4;
    bytes[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
}

/// Two half-float infinities as patch 3's radii.
fn infinite_radii(bytes: &mut [u8]) {
    let at = section(bytes, 1) + 28 * 3 + 16;
    bytes[at..at + 4].copy_from_slice(&0x7c00_7c00u32.to_le_bytes());
}

fn nan_offset(bytes: &mut [u8]) {
    bytes[32..40].copy_from_slice(&f64::NAN.to_le_bytes());
}

/// A change to a store's bytes.
type Damage = fn(&mut [u8]);

/// `store` with `damage` done to its bytes and its checksum made again, so that only the
/// checks of its numbers can refuse it.
fn damaged(store: &Path, damage: Damage) {
    let mut bytes = std::fs::read(store).unwrap();
    damage(&mut bytes);
    let body = bytes.len() - 4;
    let checksum = crc32fast::hash(&bytes[..body]);
    bytes[body..].copy_from_slice(&checksum.to_le_bytes());
    std::fs::write(store, bytes).unwrap();
}

#[test]
fn stores_with_bad_numbers_and_a_good_checksum_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let store = grid_store(dir.path());
    let good = std::fs::read(&store).unwrap();
    write_points_scene(dir.path(), "scene.toml", "grid.patches");
    let damages: [(&str, Damage); 3] =
        [("NaN block box", nan_block_box), ("infinite radii", infinite_radii), ("NaN offset", nan_offset)];
    for (what, damage) in damages {
        std::fs::write(&store, &good).unwrap();
        damaged(&store, damage);
        let (ok, stderr) = render(dir.path(), "scene.toml");
        assert!(!ok, "a store with a {what} must be refused");
        assert!(
            stderr.contains("grid.patches") && stderr.contains("malformed patch store"),
            "{what}: {stderr}"
        );
    }
}

#[test]
fn a_poisoned_cache_entry_is_regenerated_not_kept() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    write_points_scene(dir.path(), "scene.toml", "grid.ply");
    assert!(render(dir.path(), "scene.toml").0, "the first render succeeds");
    let cache = cached_store(dir.path());
    damaged(&cache, nan_block_box);
    assert!(patch_store::read(&cache).is_err(), "the entry is poisoned");
    for _ in 0..2 {
        let (ok, stderr) = render(dir.path(), "scene.toml");
        assert!(ok, "a bad cache entry must not fail the render: {stderr}");
    }
    patch_store::read(&cache).expect("the entry was replaced by a good one");
}

#[test]
fn transforms_and_shapes_beyond_f32_are_refused_clearly() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    // Scaled far beyond f32's comfort, a scene still renders: the loader scales it back. A
    // point light 2.5 units from a cloud 1e-26 across lies beyond f32 in the scene's own units.
    let directional = "[[lights]]\ntype = \"directional\"\ndirection = [-0.4, -1.0, -0.5]\n";
    let cases = [
        ("scale = 1e19", None, None),
        ("scale = 1e-25", Some(directional), None),
        ("scale = 1e-25", None, Some("lights[0].position: lies")),
        ("scale = 3e38", None, Some("scale the coordinates down")),
    ];
    for (scale, lights, expected) in cases {
        let scene = write_points_scene(dir.path(), "scene.toml", "grid.ply");
        let mut text = std::fs::read_to_string(&scene).unwrap();
        if let Some(lights) = lights {
            text = format!("{lights}{}", &text[text.find("[[objects]]").unwrap()..]);
        }
        // The transform belongs to the points object, which precedes the ground.
        let ground = "[[objects]]\ntype = \"ground\"";
        text = text.replacen(ground, &format!("[objects.transform]\n{scale}\n\n{ground}"), 1);
        std::fs::write(&scene, text).unwrap();
        let (ok, stderr) = render(dir.path(), "scene.toml");
        match expected {
            Some(expected) => assert!(!ok && stderr.contains(expected), "{scale}: {stderr}"),
            None => assert!(ok, "{scale}: {stderr}"),
        }
    }
    std::fs::write(
        dir.path().join("sphere.toml"),
        "[[objects]]\ntype = \"sphere_points\"\nradius = 1e30\ncount = 500\n[[objects]]\ntype = \"ground\"\nauto = true\n",
    )
    .unwrap();
    let (ok, stderr) = render(dir.path(), "sphere.toml");
    assert!(
        !ok && stderr.contains("objects[0]") && stderr.contains("scale the coordinates down"),
        "{stderr}"
    );
}

#[test]
fn tiny_clouds_are_refused_at_once_instead_of_hanging() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from(
        "ply\nformat ascii 1.0\nelement vertex 400\nproperty double x\nproperty double y\nproperty double z\nend_header\n",
    );
    for i in 0..400 {
        let (x, z) = ((i % 20) as f64 * 0.05e-25, (i / 20) as f64 * 0.05e-25);
        text += &format!("{x:e} {:e} {z:e}\n", 0.02e-25 * (x * 7e25).sin());
    }
    std::fs::write(dir.path().join("tiny.ply"), text).unwrap();
    let (ok, _, stderr) = pointray_in(dir.path(), &["prep", "tiny.ply", "-o", "tiny.patches"]);
    assert!(!ok && stderr.contains("tiny.ply") && stderr.contains("scale the coordinates up"), "{stderr}");
    write_points_scene(dir.path(), "scene.toml", "tiny.ply");
    let (ok, stderr) = render(dir.path(), "scene.toml");
    assert!(!ok && stderr.contains("scale the coordinates up"), "{stderr}");
}

/// A view from straight above used to be refused ("camera.up must not be parallel"), after
/// prep had written its cache, and no flag could fix it. Now such a view gets the file's north
/// as its up, `--up` sets any other, and a camera that cannot be is refused before any work.
#[test]
fn a_view_from_straight_above_renders_and_up_can_be_given() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    let above = ["--look-from", "0.5,3,0.5", "--look-at", "0.5,0,0.5"];
    let render =
        ["render", "grid.ply", "-o", "top.png", "--backend", "cpu", "--width", "16", "--height", "16"];
    let (ok, _, stderr) = pointray_in(dir.path(), &[&render[..], &above].concat());
    assert!(ok && dir.path().join("top.png").is_file(), "{stderr}");
    let east = [&render[..], &above, &["--up", "1,0,0"]].concat();
    assert!(pointray_in(dir.path(), &east).0, "--up sets the image's top");
    std::fs::remove_dir_all(dir.path().join(".pointray-cache")).unwrap();
    let parallel = [&render[..], &above, &["--up", "0,1,0"]].concat();
    let (ok, _, stderr) = pointray_in(dir.path(), &parallel);
    assert!(!ok && stderr.contains("up") && stderr.contains("parallel"), "{stderr}");
    assert!(!dir.path().join(".pointray-cache").exists(), "refused before prep wrote anything");
}

/// A scene without objects renders its background alone, as it may, but no longer silently.
#[test]
fn a_scene_without_objects_renders_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("empty.toml"), "[[lights]]\ntype = \"point\"\nposition = [0, 2, 0]\n")
        .unwrap();
    let (ok, stderr) = render(dir.path(), "empty.toml");
    assert!(ok && stderr.contains("empty.toml") && stderr.contains("no objects"), "{stderr}");
}
