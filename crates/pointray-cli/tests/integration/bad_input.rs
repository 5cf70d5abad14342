//! Every bad input gives a clear error that names the file, and a non-zero exit, never a panic.

use std::path::{Path, PathBuf};
use std::process::Command;

fn pointray(args: &[&str]) -> (bool, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_pointray")).args(args).output().expect("pointray runs");
    (output.status.success(), String::from_utf8_lossy(&output.stderr).into_owned())
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn ascii_ply(points: &[[f32; 3]]) -> Vec<u8> {
    let mut text = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
        points.len()
    );
    for [x, y, z] in points {
        text += &format!("{x} {y} {z}\n");
    }
    text.into_bytes()
}

fn binary_ply_header(count: usize) -> Vec<u8> {
    format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {count}\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
    )
    .into_bytes()
}

fn grid(count: usize) -> Vec<[f32; 3]> {
    (0..count).map(|i| [(i % 7) as f32, (i / 7) as f32, ((i * 3) % 5) as f32 * 0.1]).collect()
}

/// `prep` on `bytes` fails cleanly, and the message names the file and says `expected`.
fn assert_prep_refuses(name: &str, bytes: &[u8], expected: &str) {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), name, bytes);
    let output = dir.path().join("out.patches");
    let (ok, stderr) = pointray(&["prep", input.to_str().unwrap(), "-o", output.to_str().unwrap()]);
    assert!(!ok, "{name}: prep must fail");
    assert!(!stderr.contains("panicked"), "{name}: prep panicked: {stderr}");
    assert!(stderr.contains(name), "{name}: the error must name the file: {stderr}");
    assert!(stderr.to_lowercase().contains(expected), "{name}: expected `{expected}` in: {stderr}");
    assert!(!output.exists(), "{name}: no output may be left behind");
}

#[test]
fn empty_file() {
    assert_prep_refuses("empty.ply", b"", "empty");
}

#[test]
fn truncated_binary_body() {
    let mut bytes = binary_ply_header(100);
    bytes.extend(std::iter::repeat_n(0u8, 12 * 60));
    assert_prep_refuses("truncated.ply", &bytes, "truncated");
}

#[test]
fn header_that_lies_about_its_counts() {
    let mut bytes = binary_ply(&grid(40));
    let header_of_20 = binary_ply_header(20);
    bytes.splice(..header_of_20.len(), header_of_20);
    assert_prep_refuses("lying.ply", &bytes, "bytes");
}

fn binary_ply(points: &[[f32; 3]]) -> Vec<u8> {
    let mut bytes = binary_ply_header(points.len());
    bytes.extend(points.iter().flatten().flat_map(|v| v.to_le_bytes()));
    bytes
}

#[test]
fn non_finite_coordinates() {
    let mut points = grid(40);
    points[17] = [f32::NAN, 0.0, 0.0];
    assert_prep_refuses("nan.ply", &binary_ply(&points), "17");
    let mut points = grid(40);
    points[5] = [0.0, f32::INFINITY, 0.0];
    assert_prep_refuses("infinite.ply", &binary_ply(&points), "5");
}

#[test]
fn fewer_points_than_k_plus_one() {
    // k shrinks to the points a small cloud has, but not below 3: 3 points are too few.
    assert_prep_refuses("few.ply", &ascii_ply(&grid(3)), "3 points, but k = 3 needs at least 4");
    // The refusal says it all: no warning first that miscounts the neighbours of 2 points.
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "two.ply", &ascii_ply(&grid(2)));
    let output = dir.path().join("out.patches");
    let (ok, stderr) = pointray(&["prep", input.to_str().unwrap(), "-o", output.to_str().unwrap()]);
    assert!(!ok && stderr.contains("2 points, but k = 3"), "{stderr}");
    assert!(!stderr.contains("neighbours at most"), "{stderr}");
}

#[test]
fn all_points_identical() {
    assert_prep_refuses("same.ply", &ascii_ply(&[[1.0, 2.0, 3.0]; 50]), "identical");
}

#[test]
fn all_points_on_one_line() {
    let line: Vec<[f32; 3]> = (0..50).map(|i| [i as f32, 2.0 * i as f32, 0.5]).collect();
    assert_prep_refuses("line.ply", &ascii_ply(&line), "line");
}

#[test]
fn not_a_points_file() {
    assert_prep_refuses("notes.ply", b"\x00\x01\x02 this is not a point cloud \xff\xfe", "");
}

#[test]
fn a_damaged_patch_store_is_refused_by_render() {
    let dir = tempfile::tempdir().unwrap();
    let points = write(dir.path(), "grid.ply", &ascii_ply(&grid(200)));
    let store = dir.path().join("grid.patches");
    let (ok, stderr) = pointray(&["prep", points.to_str().unwrap(), "-o", store.to_str().unwrap()]);
    assert!(ok, "prep of a good grid succeeds: {stderr}");
    let good = std::fs::read(&store).unwrap();
    let scene = write(
        dir.path(),
        "scene.toml",
        b"[[lights]]\ntype = \"point\"\nposition = [0.0, 10.0, 10.0]\n\n[[objects]]\ntype = \"points\"\npath = \"grid.patches\"\n",
    );
    let image = dir.path().join("out.png");
    let mut damaged = [(good.clone(), "checksum"), (good, "version")];
    damaged[0].0[200] ^= 0x40;
    damaged[1].0[8] = 99;
    for (bytes, expected) in damaged {
        std::fs::write(&store, bytes).unwrap();
        let (ok, stderr) = pointray(&[
            "render",
            scene.to_str().unwrap(),
            "-o",
            image.to_str().unwrap(),
            "--backend",
            "cpu",
            "--width",
            "16",
            "--height",
            "16",
        ]);
        assert!(!ok, "a damaged store ({expected}) must be refused");
        assert!(!stderr.contains("panicked"), "render panicked: {stderr}");
        assert!(stderr.contains("grid.patches"), "the error must name the store: {stderr}");
        assert!(stderr.to_lowercase().contains(expected), "expected `{expected}` in: {stderr}");
    }
}

#[test]
fn errors_never_print_the_contents_of_a_file_named_by_mistake() {
    let dir = tempfile::tempdir().unwrap();
    let secret = "root:x:0:0:SECRET-MARKER:/root:/bin/bash\n";
    let system_file = write(dir.path(), "passwd", secret.as_bytes());
    let scene = write(
        dir.path(),
        "scene.toml",
        format!("[[objects]]\ntype = \"points\"\npath = \"{}\"\n", system_file.display()).as_bytes(),
    );
    let image = dir.path().join("out.png");
    for input in [scene, system_file] {
        let (ok, stderr) = pointray(&["render", input.to_str().unwrap(), "-o", image.to_str().unwrap()]);
        assert!(!ok && stderr.contains("passwd"), "the error names the file: {stderr}");
        assert!(!stderr.contains("SECRET-MARKER"), "the file's contents were printed: {stderr}");
    }
    let lookalikes = [
        ("mesh.obj", "v 0 0 0\nv SECRET-MARKER 1 1\nf 1 2 3\n"),
        ("corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 SECRET-MARKER\n"),
        ("header.ply", "ply\nformat ascii 1.0\nelement vertex 2 SECRET-MARKER\nend_header\n"),
    ];
    for (name, text) in lookalikes {
        let input = write(dir.path(), name, text.as_bytes());
        let output = dir.path().join("out.patches");
        let (ok, stderr) = pointray(&["prep", input.to_str().unwrap(), "-o", output.to_str().unwrap()]);
        assert!(!ok && stderr.contains(name), "{name}: {stderr}");
        assert!(!stderr.contains("SECRET-MARKER"), "{name}: the file's contents were printed: {stderr}");
    }
}

#[test]
fn folders_and_devices_are_named_as_such() {
    let dir = tempfile::tempdir().unwrap();
    let image = dir.path().join("out.png");
    let (ok, stderr) = pointray(&["render", dir.path().to_str().unwrap(), "-o", image.to_str().unwrap()]);
    assert!(!ok && stderr.contains("is a folder, not a file"), "{stderr}");
    let (ok, stderr) = pointray(&["prep", dir.path().to_str().unwrap(), "-o", image.to_str().unwrap()]);
    assert!(!ok && stderr.contains("is a folder, not a file"), "{stderr}");
    #[cfg(unix)]
    {
        let (ok, stderr) =
            pointray(&["prep", "/dev/zero", "-o", dir.path().join("z.patches").to_str().unwrap()]);
        assert!(!ok && stderr.contains("is a device, not a file"), "{stderr}");
    }
}

/// A NaN intensity used to prep into a store that no renderer would load; now prep refuses it,
/// naming the file and the point, whole and in tiles (streamed).
#[test]
fn a_nan_intensity_is_refused_at_prep_naming_the_point() {
    let header = "ply\nformat binary_little_endian 1.0\nelement vertex 400\nproperty float x\nproperty float y\n\
                  property float z\nproperty float intensity\nend_header\n";
    let mut bytes = header.as_bytes().to_vec();
    for (i, [x, y, z]) in grid(400).into_iter().enumerate() {
        let intensity = if i == 123 { f32::NAN } else { 0.5 };
        bytes.extend([x, y, z, intensity].iter().flat_map(|v| v.to_le_bytes()));
    }
    assert_prep_refuses("nan_intensity.ply", &bytes, "point 123 has an intensity that is nan");
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "nan_intensity.ply", &bytes);
    let output = dir.path().join("out.patches");
    let args = ["prep", input.to_str().unwrap(), "-o", output.to_str().unwrap(), "--tiles", "2"];
    let (ok, stderr) = pointray(&args);
    assert!(!ok && stderr.contains("nan_intensity.ply") && stderr.contains("point 123 has"), "{stderr}");
    assert!(!output.exists());
}

/// `view --arc nan` (or `inf`) saved a black screenshot with exit 0; the flag is refused as
/// it is parsed, before a window opens.
#[test]
fn a_view_arc_that_is_not_finite_is_refused() {
    for arc in ["nan", "inf", "ninety"] {
        let (ok, stderr) = pointray(&["view", "scene.toml", "--frames", "2", "--arc", arc]);
        assert!(
            !ok && stderr.contains("--arc") && stderr.contains("finite number of degrees"),
            "{arc}: {stderr}"
        );
    }
}

/// `sample` on a mesh without area wrote a file of no points with exit 0, and `-o x.las` wrote
/// PLY bytes under a LAS name; both are refused, and nothing is written.
#[test]
fn sample_refuses_a_mesh_without_area_and_an_output_it_cannot_write() {
    let dir = tempfile::tempdir().unwrap();
    let flat = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 1 1\n2 2 2\n3 0 1 2\n";
    let mesh = write(dir.path(), "line.ply", flat.as_bytes());
    let mesh = mesh.to_str().unwrap();
    let output = dir.path().join("out.ply");
    let (ok, stderr) = pointray(&["sample", mesh, "-o", output.to_str().unwrap(), "--count", "100"]);
    assert!(!ok && stderr.contains("line.ply") && stderr.contains("no area"), "{stderr}");
    assert!(!output.exists());
    let las = dir.path().join("out.las");
    let (ok, stderr) = pointray(&["sample", mesh, "-o", las.to_str().unwrap(), "--count", "100"]);
    assert!(!ok && stderr.contains("out.las") && stderr.contains("*.ply"), "{stderr}");
    assert!(!las.exists());
}

/// More tiles than points left tiles with no points of their own, which ended in an overflow
/// (debug) or "Invalid argument" on a temporary path (release); now a clear refusal.
#[test]
fn more_tiles_than_points_are_refused_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "grid.ply", &ascii_ply(&grid(100)));
    let output = dir.path().join("out.patches");
    for tiles in [["--tiles", "101"], ["--tile", "3"]] {
        let mut args = vec!["prep", input.to_str().unwrap(), "-o", output.to_str().unwrap()];
        args.extend(tiles);
        if tiles[0] == "--tile" {
            args.extend(["--of", "101"]);
        }
        let (ok, stderr) = pointray(&args);
        assert!(
            !ok && stderr.contains("grid.ply") && stderr.contains("101 tiles asked for"),
            "{args:?}: {stderr}"
        );
        assert!(!stderr.contains("panicked") && !stderr.contains("os error"), "{stderr}");
    }
}

/// A PCD field of several values a point is left out with one warning: a file read whole is
/// read once, not once to size the prep and again to prep it.
#[test]
fn a_pcd_multi_count_field_is_warned_about_once() {
    let dir = tempfile::tempdir().unwrap();
    let points = grid(100);
    let mut text = format!(
        "VERSION .7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 4\nWIDTH {0}\n\
         HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {0}\nDATA ascii\n",
        points.len()
    );
    for [x, y, z] in &points {
        text += &format!("{x} {y} {z} 0.1 0.2 0.3 0.4\n");
    }
    let input = write(dir.path(), "multi.pcd", text.as_bytes());
    let output = dir.path().join("out.patches");
    let (ok, stderr) = pointray(&["prep", input.to_str().unwrap(), "-o", output.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert_eq!(stderr.matches("has COUNT 4; it is left out").count(), 1, "{stderr}");
}
