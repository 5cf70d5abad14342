//! `pointray prep` on geo-referenced coordinates (~10^6): it prints the f64 recentring
//! offset, stores exactly that offset, and the stored patches keep millimetres.

use std::process::Command;

use glam::DVec3;
use pointray_io::PointCloud;

/// A gently curved 40x40 grid, 10 m a side, around a UTM-like position.
const ORIGIN: DVec3 = DVec3::new(636_512.437_5, 849_203.187_5, 132.062_5);

fn geo_cloud() -> PointCloud {
    let positions = (0..1600)
        .map(|i| {
            let (x, y) = (0.25 * (i % 40) as f64, 0.25 * (i / 40) as f64);
            ORIGIN + DVec3::new(x, y, 0.01 * (x * x + y))
        })
        .collect();
    PointCloud::from_positions(positions)
}

/// The three numbers after "recentring offset ...:" in prep's output.
fn printed_offset(stdout: &str) -> DVec3 {
    let line =
        stdout.lines().find(|line| line.starts_with("recentring offset")).expect("prep reports the offset");
    let numbers: Vec<f64> =
        line.rsplit(':').next().unwrap().split(',').map(|part| part.trim().parse().unwrap()).collect();
    DVec3::from_slice(&numbers)
}

#[test]
fn the_printed_offset_is_the_stored_offset_and_positions_survive() {
    let dir = tempfile::tempdir().unwrap();
    let (input, store) = (dir.path().join("geo.ply"), dir.path().join("geo.patches"));
    let cloud = geo_cloud();
    pointray_io::formats::ply::write_point_cloud(&input, &cloud).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_pointray"))
        .args(["prep", input.to_str().unwrap(), "-o", store.to_str().unwrap()])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}{}", String::from_utf8_lossy(&output.stderr));

    let offset = printed_offset(&stdout);
    let patches = pointray_patches::patch_store::read(&store).unwrap();
    assert_eq!(patches.offset, offset, "the store holds exactly the printed offset");
    assert!(
        offset.distance(ORIGIN + DVec3::new(4.875, 4.875, 0.0)).abs() < 1.0,
        "offset {offset} is the centre"
    );

    // Every patch sits on an input point to well under a millimetre, which an f32 of the
    // raw coordinates (ulp 0.06 m at 8.5e5) could not do.
    let tree: Vec<DVec3> = cloud.positions.clone();
    for hot in &patches.hot {
        let restored = hot.origin().as_dvec3() + patches.offset;
        let nearest = tree.iter().map(|p| p.distance(restored)).fold(f64::INFINITY, f64::min);
        assert!(nearest < 1e-4, "patch at {restored} is {nearest} m from every input point");
    }
}
