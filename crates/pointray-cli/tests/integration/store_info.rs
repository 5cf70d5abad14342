//! `pointray info`: a store's header in words, with the scan structure prep found, and a
//! store of an older version refused by name with the way out.

use std::path::Path;

use pointray_test_support::data_file;

use crate::common::{pointray_in, write_grid_ply};

fn succeeds(dir: &Path, args: &[&str]) -> String {
    let (ok, stdout, stderr) = pointray_in(dir, args);
    assert!(ok, "pointray {args:?} failed:\n{stdout}\n{stderr}");
    stdout
}

#[test]
fn info_shows_the_scan_lines_prep_found_in_a_real_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = data_file("scans/real/ouster_os1_32/scan00.bin");
    let prepped = succeeds(dir.path(), &["prep", sweep.to_str().unwrap(), "-o", "sweep.patches"]);
    let lines = prepped
        .lines()
        .find_map(|line| line.strip_prefix("scan-aware: ")?.split(" scan lines").next())
        .unwrap_or_else(|| panic!("prep found no scan lines:\n{prepped}"));
    let info = succeeds(dir.path(), &["info", "sweep.patches"]);
    assert!(info.contains(&format!("scan structure: {lines} scan lines, ")), "{info}");
    assert!(info.contains("patch store version 9"), "{info}");
    assert!(info.contains("compact, with colours and intensities"), "{info}");
}

/// A folder holding a 400-point grid prepped into `store`.
fn prepped_grid(store: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    succeeds(dir.path(), &["prep", "grid.ply", "-o", store]);
    dir
}

#[test]
fn info_says_no_scan_structure_was_sought_for_points_without_a_sensor() {
    let dir = prepped_grid("grid.patches");
    let info = succeeds(dir.path(), &["info", "grid.patches"]);
    assert!(info.contains("scan structure: none sought"), "{info}");
    assert!(info.contains("patches: 400 ("), "{info}");
    let coarse: u64 = (info.lines().find_map(|line| line.strip_prefix("coarse patches: ")))
        .and_then(|rest| rest.split(' ').next()?.parse().ok())
        .unwrap_or_else(|| panic!("info gives the coarse level's patches:\n{info}"));
    assert!((10..100).contains(&coarse), "{info}");
}

#[test]
fn a_store_of_an_older_version_is_refused_with_the_way_out() {
    let dir = prepped_grid("old.patches");
    let store = dir.path().join("old.patches");
    let mut bytes = std::fs::read(&store).unwrap();
    bytes[8..12].copy_from_slice(&8u32.to_le_bytes());
    std::fs::write(&store, bytes).unwrap();
    for args in [&["info", "old.patches"][..], &["render", "old.patches", "-o", "out.png"]] {
        let (ok, _, stderr) = pointray_in(dir.path(), args);
        assert!(!ok, "{args:?} read an old store");
        let refusal =
            "old.patches: patch store version 8, this build reads version 9 only: re-run `pointray prep`";
        assert!(stderr.contains(refusal), "{args:?}: {stderr}");
    }
}
