//! Prep in bounded memory from the command line: tiles prepped as separate processes in
//! parallel merge into the store one process writes, byte for byte; and a `--memory` budget
//! several times smaller than the in-memory prep of a cloud holds the process's peak.

use std::path::Path;
use std::process::{Command, Stdio};

use glam::DVec3;
use pointray_io::PointCloud;
use pointray_io::formats::ply::write_point_cloud;

use crate::common::pointray_in;

/// A wavy coloured sheet of `side` x `side` points, jittered, as binary PLY.
fn write_sheet(path: &Path, side: usize) {
    let positions: Vec<DVec3> = (0..side * side)
        .map(|i| {
            let (x, y) = ((i % side) as f64 / side as f64, (i / side) as f64 / side as f64);
            let jitter = ((i as f64 * 0.618_034).fract() - 0.5) * 0.3 / side as f64;
            DVec3::new(x + jitter, y - jitter, 0.05 * (6.0 * x).sin() * (4.0 * y).cos())
        })
        .collect();
    let colors = (0..positions.len()).map(|i| [(i % 251) as u8, (i % 13) as u8 * 19, 90]).collect();
    write_point_cloud(path, &PointCloud { colors: Some(colors), ..PointCloud::from_positions(positions) })
        .unwrap();
}

#[test]
fn tiles_prepped_by_parallel_processes_merge_into_the_single_process_store() {
    let dir = tempfile::tempdir().unwrap();
    write_sheet(&dir.path().join("sheet.ply"), 150);
    let sensor = ["--sensor", "0.5,0.5,2", "--scan", "off", "--memory", "1G"];
    let single = [&["prep", "sheet.ply", "-o", "single.patches", "--tiles", "4"][..], &sensor].concat();
    let (ok, _, stderr) = pointray_in(dir.path(), &single);
    assert!(ok, "{stderr}");
    let jobs: Vec<_> = (0..4)
        .map(|i| {
            Command::new(env!("CARGO_BIN_EXE_pointray"))
                .current_dir(dir.path())
                .args([
                    "prep",
                    "sheet.ply",
                    "-o",
                    &format!("tile{i}.tile"),
                    "--tile",
                    &i.to_string(),
                    "--of",
                    "4",
                ])
                .args(sensor)
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    for job in jobs {
        let output = job.wait_with_output().unwrap();
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    }
    let merge =
        ["prep", "--merge", "tile2.tile", "tile0.tile", "tile3.tile", "tile1.tile", "-o", "merged.patches"];
    let (ok, stdout, stderr) = pointray_in(dir.path(), &merge);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("of 4 tiles"), "{stdout}");
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert!(read("merged.patches") == read("single.patches"), "the merged store is the single process's");
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 7, "no scratch folder is left: {left:?}");

    // The same jobs on one sort kept for them write the same tiles.
    let keep = [&["prep", "sheet.ply", "--keep-sort", "-o", "sheet.sorted"][..], &sensor].concat();
    let (ok, stdout, stderr) = pointray_in(dir.path(), &keep);
    assert!(ok && stdout.contains("sorted 22500 points into sheet.sorted"), "{stdout}{stderr}");
    for i in 0..4 {
        let (tile, index) = (format!("kept{i}.tile"), i.to_string());
        let job = [&["prep", "sheet.sorted", "-o", &tile, "--tile", &index, "--of", "4"][..], &sensor];
        let (ok, _, stderr) = pointray_in(dir.path(), &job.concat());
        assert!(ok, "{stderr}");
        assert!(read(&tile) == read(&format!("tile{i}.tile")), "tile {i} from the kept sort");
    }
    let kept_tiles = ["kept0.tile", "kept1.tile", "kept2.tile", "kept3.tile"];
    let merge =
        [&["prep", "--merge"][..], &kept_tiles, &["-o", "removed.patches", "--remove-tiles"]].concat();
    let (ok, _, stderr) = pointray_in(dir.path(), &merge);
    assert!(ok, "{stderr}");
    assert!(read("removed.patches") == read("single.patches"), "tiles removed as they are merged");
    assert!(kept_tiles.iter().all(|tile| !dir.path().join(tile).exists()), "each tile removed");
    let whole = [&["prep", "sheet.sorted", "-o", "kept.patches", "--tiles", "4"][..], &sensor].concat();
    let (ok, _, stderr) = pointray_in(dir.path(), &whole);
    assert!(ok, "{stderr}");
    assert!(read("kept.patches") == read("single.patches"), "the whole store from the kept sort");

    let (ok, _, stderr) = pointray_in(dir.path(), &["prep", "--merge", "tile0.tile", "-o", "part.patches"]);
    assert!(!ok && stderr.contains("tile 1 of 4 is missing"), "{stderr}");
    let (ok, _, stderr) = pointray_in(dir.path(), &["prep", "--merge", "tile0.tile", "-o", "tile0.tile"]);
    assert!(!ok && stderr.contains("refusing to write over the input"), "{stderr}");
}

#[test]
fn a_memory_budget_smaller_than_the_cloud_holds_the_peak() {
    const BUDGET: u64 = 40 << 20;
    let dir = tempfile::tempdir().unwrap();
    let side = 600;
    write_sheet(&dir.path().join("sheet.ply"), side);
    // The process's own high-water mark (VmHWM), which starts afresh at exec: a parent's
    // rusage of a forked child also counts the pages it shared with the parent before.
    let (ok, stdout, stderr) = pointray_in(
        dir.path(),
        &["prep", "sheet.ply", "-o", "bounded.patches", "--memory", &BUDGET.to_string()],
    );
    assert!(ok, "prep within the budget succeeds: {stderr}");
    let peak_kib: u64 = stdout
        .split("peak resident memory ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|kib| kib.parse().ok())
        .unwrap_or_else(|| panic!("prep reports its peak: {stdout}"));
    let (ok, _, stderr) =
        pointray_in(dir.path(), &["prep", "sheet.ply", "-o", "whole.patches", "--memory", "4G"]);
    assert!(ok, "prep in memory succeeds: {stderr}");
    // In memory the same cloud takes more than 300 bytes a point (94 MiB measured).
    let in_memory = (side * side) as u64 * 300;
    eprintln!("peak RSS {} MiB within a {} MiB budget", peak_kib >> 10, BUDGET >> 20);
    assert!(in_memory >= 2 * BUDGET, "the cloud's prep in memory is several times the budget");
    assert!(peak_kib << 10 <= BUDGET, "peak RSS {peak_kib} KiB over the {BUDGET}-byte budget");
    let patches =
        |name: &str| pointray_patches::patch_store::describe(&dir.path().join(name)).unwrap().patches;
    assert_eq!(patches("bounded.patches"), patches("whole.patches"), "every point has its patch either way");
}
