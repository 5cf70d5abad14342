//! Inputs the fuzzers once crashed on (`fuzz/regressions/TARGET/`), replayed through the
//! plain readers: each must now give an error, not a panic or a runaway allocation.

use std::io::Cursor;
use std::path::{Path, PathBuf};

use pointray_io::IoError;
use pointray_io::formats::{e57, las, pcd, raw_bin, xyz};

fn regressions(target: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/regressions").join(target);
    let Ok(entries) = std::fs::read_dir(&dir) else { return Vec::new() };
    entries.map(|entry| entry.unwrap().path()).collect()
}

fn read_with(target: &str, bytes: Vec<u8>, origin: &Path) -> Result<pointray_io::PointCloud, IoError> {
    match target {
        "las" => las::read_las_from(Cursor::new(bytes), origin),
        "pcd" => pcd::read_pcd_from(&bytes, origin),
        "e57" => e57::read_e57_from(Cursor::new(bytes), origin),
        "xyz" => xyz::read_xyz_from(&bytes, origin, None),
        "raw_bin" => raw_bin::read_raw_bin_from(&bytes, origin, None),
        other => panic!("no reader for fuzz target {other}"),
    }
}

#[test]
fn every_recorded_crash_is_now_a_clear_error() {
    let mut replayed = 0;
    for target in ["las", "pcd", "e57", "xyz", "raw_bin"] {
        for path in regressions(target) {
            let bytes = std::fs::read(&path).unwrap();
            let error =
                read_with(target, bytes, &path).expect_err("a crashing input cannot be a valid cloud");
            assert!(error.to_string().contains(&path.display().to_string()), "{error}");
            replayed += 1;
        }
    }
    assert!(replayed >= 5, "only {replayed} regression inputs found");
}
