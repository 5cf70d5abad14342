//! `pointray scan`: the street end to end, and every bad argument refused clearly.

use std::path::Path;
use std::process::Command;

/// Runs pointray; (success, stdout, stderr).
fn pointray(args: &[&str]) -> (bool, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_pointray")).args(args).output().expect("pointray runs");
    let text = |bytes: &[u8]| String::from_utf8_lossy(bytes).into_owned();
    (output.status.success(), text(&output.stdout), text(&output.stderr))
}

fn path_str(path: &Path) -> &str {
    path.to_str().unwrap()
}

#[test]
fn the_street_is_scanned_into_the_fixed_layout_with_its_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let (points, mesh) = (dir.path().join("scan.ply"), dir.path().join("street.ply"));
    let args = ["scan", "--street", "--sensor", "vlp16", "--azimuth-step", "10", "--seed", "4", "-o"];
    let (ok, stdout, stderr) =
        pointray(&[&args[..], &[path_str(&points), "--mesh-out", path_str(&mesh)]].concat());
    assert!(ok, "scan failed: {stderr}");
    assert!(stdout.contains("returns of 576 rays"), "{stdout}");
    let bytes = std::fs::read(&points).unwrap();
    let header_end = bytes.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let header = std::str::from_utf8(&bytes[..header_end]).unwrap();
    for property in ["double x", "float intensity", "ushort ring", "uchar classification", "double sensor_z"]
    {
        assert!(header.contains(&format!("property {property}\n")), "{header}");
    }
    let cloud = pointray_io::formats::read_point_cloud(&points).unwrap();
    assert_eq!(bytes.len() - header_end, cloud.len() * 63);
    let street = pointray_io::formats::read_triangle_mesh(&mesh).unwrap();
    assert!(street.triangles.len() > 1000);

    let again = dir.path().join("again.ply");
    let (ok, _, stderr) = pointray(&[&args[..], &[path_str(&again)]].concat());
    assert!(ok, "{stderr}");
    assert_eq!(std::fs::read(&again).unwrap(), bytes, "the same seed must give the same file");
}

/// The command fails cleanly with `expected` in its message and leaves no output behind.
fn assert_refused(args: &[&str], expected: &str) {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("out.ply");
    let (ok, _, stderr) = pointray(&[&["scan"], args, &["-o", path_str(&output)]].concat());
    assert!(!ok, "{args:?} must fail");
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    assert!(stderr.contains(expected), "{args:?}: expected `{expected}` in: {stderr}");
    assert!(!output.exists(), "{args:?}: no output may be left behind");
}

#[test]
fn bad_sensor_settings() {
    let street = ["--street", "--sensor", "vlp16"];
    let with = |extra: &[&'static str]| [&street[..], extra].concat();
    assert_refused(&with(&["--dropout", "1.5"]), "--dropout");
    assert_refused(&with(&["--noise", "-0.1"]), "--noise");
    assert_refused(&with(&["--min-range", "5", "--max-range", "2"]), "--max-range");
    assert_refused(&with(&["--azimuth-step", "0"]), "--azimuth-step");
    assert_refused(&with(&["--azimuth-step", "0.000001"]), "rays");
    assert_refused(&with(&["--position", "1,2"]), "x,y,z");
    assert_refused(&with(&["--position", "nan,0,1"]), "--position");
    assert_refused(&with(&["--stations", "0,0,1;5,0,inf"]), "station 1");
    assert_refused(&with(&["--yaw", "inf"]), "--yaw");
    assert_refused(&with(&["--max-range", "1.5", "--position", "0,0,50"]), "no returns");
    assert_refused(&["--street", "--sensor", "hdl65"], "unknown sensor `hdl65`");
}

#[test]
fn bad_scenes_and_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("floor.toml");
    std::fs::write(&scene, "[[objects]]\ntype = \"ground\"\nsize = 20.0\n").unwrap();
    let scene = path_str(&scene);
    assert_refused(&[scene, "--sensor", "vlp16"], "--position");
    assert_refused(&[scene, "--sensor", "vlp16", "--mesh-out", "m.ply"], "--street");
    assert_refused(&[scene, "--street", "--sensor", "vlp16"], "cannot be used with");
    assert_refused(&["--sensor", "vlp16"], "required");
    let missing = dir.path().join("missing.toml");
    assert_refused(&[path_str(&missing), "--sensor", "vlp16", "--position", "0,1,0"], "missing.toml");

    // A scene file scans from a given position, Y up.
    let points = dir.path().join("floor_scan.ply");
    let (ok, stdout, stderr) = pointray(&[
        "scan",
        scene,
        "--sensor",
        "vlp16",
        "--position",
        "0,1.5,0",
        "--noise",
        "0",
        "-o",
        path_str(&points),
    ]);
    assert!(ok && stdout.contains("up axis +Y"), "{stdout} {stderr}");
    let cloud = pointray_io::formats::read_point_cloud(&points).unwrap();
    assert!(cloud.positions.iter().all(|p| p.y.abs() < 1e-3), "returns off the floor y = 0");
    // Never over the scene it reads, nor one output over the other.
    let (ok, _, stderr) =
        pointray(&["scan", scene, "--sensor", "vlp16", "--position", "0,1.5,0", "-o", scene]);
    assert!(!ok && stderr.contains("refusing"), "{stderr}");
    let twice = path_str(&points);
    let (ok, _, stderr) =
        pointray(&["scan", "--street", "--sensor", "vlp16", "-o", twice, "--mesh-out", twice]);
    assert!(!ok && stderr.contains("each output needs a file of its own"), "{stderr}");
}

/// The returns are written as PLY: `-o x.las` used to put PLY bytes under a LAS name.
#[test]
fn a_scan_output_not_named_ply_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("x.las");
    let (ok, _, stderr) = pointray(&["scan", "--street", "--sensor", "vlp16", "-o", path_str(&output)]);
    assert!(!ok && stderr.contains("x.las") && stderr.contains("*.ply"), "{stderr}");
    assert!(!output.exists());
}
