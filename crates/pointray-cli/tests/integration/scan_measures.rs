//! `fidelity` on a scan's own views and `consistency`, end to end on a KITTI-style sweep of
//! flat ground, and their clear errors for bad arguments.

use std::path::{Path, PathBuf};
use std::process::Command;

fn pointray(args: &[&str]) -> (bool, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_pointray")).args(args).output().expect("pointray runs");
    let text = |bytes: &[u8]| String::from_utf8_lossy(bytes).into_owned();
    (output.status.success(), text(&output.stdout), text(&output.stderr))
}

/// A KITTI `.bin` sweep (sensor at the origin) of the ground 2 below it: rings every degree
/// from -40° to -12°, a return every 2° of azimuth.
fn write_ground_sweep(dir: &Path) -> PathBuf {
    let mut bytes = Vec::new();
    for elevation in -40..=-12 {
        for azimuth in (0..360).step_by(2) {
            let (e, a) = (f64::from(elevation).to_radians(), f64::from(azimuth).to_radians());
            let range = 2.0 / -e.sin();
            let point = [e.cos() * a.cos() * range, e.cos() * a.sin() * range, -2.0, 0.5];
            bytes.extend(point.iter().flat_map(|&c| (c as f32).to_le_bytes()));
        }
    }
    let path = dir.join("ground.bin");
    std::fs::write(&path, bytes).unwrap();
    path
}

/// The ground as a mesh: a square 40 wide at z = -2.
fn write_ground_mesh(dir: &Path) -> PathBuf {
    let text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
                element face 2\nproperty list uchar int vertex_indices\nend_header\n\
                -20 -20 -2\n20 -20 -2\n20 20 -2\n-20 20 -2\n3 0 1 2\n3 0 2 3\n";
    let path = dir.join("ground_mesh.ply");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn consistency_of_a_ground_sweep_is_near_total_and_written_as_json() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = write_ground_sweep(dir.path());
    let json = dir.path().join("consistency.json");
    let (ok, stdout, stderr) =
        pointray(&["consistency", sweep.to_str().unwrap(), "--json", json.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("consistent:") && stdout.contains("passed through:"), "{stdout}");
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["counts"]["rays"], 29 * 180);
    assert!(report["consistent_fraction"].as_f64().unwrap() >= 0.99, "{report}");
}

#[test]
fn fidelity_from_the_sensor_and_from_above_names_its_views() {
    let dir = tempfile::tempdir().unwrap();
    let (sweep, mesh) = (write_ground_sweep(dir.path()), write_ground_mesh(dir.path()));
    let args =
        [sweep.to_str().unwrap(), mesh.to_str().unwrap(), "--views", "sensor,above:15", "--size", "48"];
    let (ok, stdout, stderr) = pointray(&[&["fidelity"], &args[..]].concat());
    assert!(ok, "{stderr}");
    for label in ["sensor yaw +0°", "sensor yaw +90°", "sensor yaw +180°", "sensor yaw +270°", "above 15"]
    {
        assert!(stdout.contains(label), "no `{label}` view in:\n{stdout}");
    }
}

#[test]
fn bad_view_and_tolerance_arguments_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let (sweep, mesh) = (write_ground_sweep(dir.path()), write_ground_mesh(dir.path()));
    let (sweep, mesh) = (sweep.to_str().unwrap(), mesh.to_str().unwrap());
    let cases: [(&[&str], &str); 9] = [
        (&["fidelity", sweep, mesh, "--views", "below"], "unknown view `below`"),
        (&["fidelity", sweep, mesh, "--views", "sensor:2"], "3 to 12 yaws"),
        (&["fidelity", sweep, mesh, "--views", "above:-3"], "positive"),
        (&["fidelity", sweep, mesh, "--view-from", "1,2,3"], "--view-at 0 targets"),
        (&["fidelity", sweep, mesh, "--view-from", "nan,0,0", "--view-at", "0,0,0"], "not a finite point"),
        (&["fidelity", sweep, mesh, "--view-from", "1,1,1", "--view-at", "1,1,1"], "stands on its target"),
        (&["fidelity", sweep, mesh, "--views", "above", "--fov", "-10"], "field of view"),
        (&["consistency", sweep, "--abs-tolerance", "-1"], "range tolerance"),
        (&["consistency", sweep, "--rays", "0"], "ray budget"),
    ];
    for (args, expected) in cases {
        let (ok, _, stderr) = pointray(args);
        assert!(!ok, "{args:?} must fail");
        assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: expected `{expected}` in: {stderr}");
    }
}

#[test]
fn sensor_views_and_consistency_need_a_sensor_and_say_how_to_give_one() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = write_ground_mesh(dir.path());
    let (mesh, points) = (mesh.to_str().unwrap(), dir.path().join("points.ply"));
    let vertices: String = (0..100).map(|i| format!("{} {} -2\n", i % 10, i / 10)).collect();
    let header = "ply\nformat ascii 1.0\nelement vertex 100\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    std::fs::write(&points, format!("{header}{vertices}")).unwrap();
    let points = points.to_str().unwrap();
    for args in [&["fidelity", points, mesh, "--views", "sensor"][..], &["consistency", points][..]] {
        let (ok, _, stderr) = pointray(args);
        assert!(!ok && stderr.contains("--sensor") && stderr.contains("points.ply"), "{args:?}: {stderr}");
    }
}
