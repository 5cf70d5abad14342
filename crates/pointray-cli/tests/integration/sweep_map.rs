//! Real Ouster OS-1-128 sweeps (data/scans/real/ouster_os1_128_seq/, data/SOURCES.md) merged
//! into a map with their poses, and a sweep's rays re-simulated in it: `prep A.bin B.bin
//! --poses`, then `scan MAP --rays-from SWEEP.bin --poses … --json`. And the ways these
//! commands refuse what they cannot do.

use std::path::{Path, PathBuf};

use pointray_test_support::data_file;

use crate::common::pointray_in;

/// Bytes of a KITTI record: x, y, z, intensity, each a float32.
const RECORD_BYTES: usize = 16;

fn sequence(name: &str) -> PathBuf {
    data_file(&format!("scans/real/ouster_os1_128_seq/{name}"))
}

fn path_str(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Runs pointray in `dir` and fails the test, with its output, unless it succeeds.
fn succeeds(dir: &Path, args: &[&str]) -> String {
    let (ok, stdout, stderr) = pointray_in(dir, args);
    assert!(ok, "pointray {args:?} failed:\n{stdout}\n{stderr}");
    stdout
}

/// Preps `sweeps` of the sequence, placed by its poses, into `dir/map.patches`.
fn map_of(dir: &Path, sweeps: &[&str]) -> PathBuf {
    let map = dir.join("map.patches");
    let sweeps: Vec<PathBuf> = sweeps.iter().map(|name| sequence(name)).collect();
    let poses = sequence("poses_kitti.txt");
    let mut args = vec!["prep"];
    args.extend(sweeps.iter().map(|sweep| path_str(sweep)));
    args.extend(["--poses", path_str(&poses), "-o", path_str(&map)]);
    succeeds(dir, &args);
    map
}

/// What `scan --json` wrote: agreeing_fraction and chamfer.
struct Scores {
    agreeing_fraction: f64,
    chamfer: f64,
}

/// Re-simulates `sweep` of the sequence in `map` from its pose; the scores, and the sweep
/// written, in `dir`.
fn resimulated(dir: &Path, map: &Path, sweep: &str) -> (Scores, Vec<u8>) {
    let (output, json) = (dir.join("out.bin"), dir.join("r.json"));
    let (sweep, poses) = (sequence(sweep), sequence("poses_kitti.txt"));
    let args = ["scan", path_str(map), "--rays-from", path_str(&sweep), "--poses", path_str(&poses)];
    let stdout = succeeds(dir, &[&args[..], &["-o", path_str(&output), "--json", path_str(&json)]].concat());
    println!("{stdout}");
    let report: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let number =
        |field: &str| report[field].as_f64().unwrap_or_else(|| panic!("no number `{field}` in {report:#}"));
    let scores = Scores { agreeing_fraction: number("agreeing_fraction"), chamfer: number("chamfer") };
    (scores, std::fs::read(&output).unwrap())
}

/// scan01 re-simulated from a map of scan00 and scan02, the sweeps either side of it: at least
/// 90% of ranges agree (90.2% in release, Chamfer 0.057 m).
#[test]
fn a_sweep_between_two_others_is_re_simulated_in_their_map() {
    let dir = tempfile::tempdir().unwrap();
    let map = map_of(dir.path(), &["scan00.bin", "scan02.bin"]);
    let (scores, sweep) = resimulated(dir.path(), &map, "scan01.bin");
    assert!(scores.agreeing_fraction >= 0.90, "{:.2}% agree", 100.0 * scores.agreeing_fraction);
    assert!(scores.chamfer <= 0.10, "Chamfer {:.3} m", scores.chamfer);
    assert!(!sweep.is_empty() && sweep.len().is_multiple_of(RECORD_BYTES), "{} bytes", sweep.len());
}

/// scan02, 0.5 m on, re-simulated from a map of scan00 alone: the ranges agree less (80% in
/// release, what scan00 did not see), but the surfaces it did see lie where scan02 saw them
/// (Chamfer 0.076 m in release).
#[test]
fn a_sweep_re_simulated_in_the_map_of_an_earlier_one_lies_on_its_surfaces() {
    let dir = tempfile::tempdir().unwrap();
    let map = map_of(dir.path(), &["scan00.bin"]);
    let (scores, sweep) = resimulated(dir.path(), &map, "scan02.bin");
    assert!(scores.chamfer <= 0.10, "Chamfer {:.3} m", scores.chamfer);
    assert!(!sweep.is_empty() && sweep.len().is_multiple_of(RECORD_BYTES), "{} bytes", sweep.len());
}

/// The command fails cleanly with `expected` in its message, and writes no `output`; its
/// message.
fn assert_refused(dir: &Path, args: &[&str], output: &Path, expected: &str) -> String {
    let (ok, _, stderr) = pointray_in(dir, args);
    assert!(!ok, "{args:?} must fail");
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    assert!(stderr.contains(expected), "{args:?}: expected `{expected}` in: {stderr}");
    assert!(!output.exists(), "{args:?}: no output may be left behind");
    stderr
}

#[test]
fn several_sweeps_without_poses_are_refused_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (sequence("scan00.bin"), sequence("scan01.bin"));
    let map = dir.path().join("x.patches");
    assert_refused(dir.path(), &["prep", path_str(&a), path_str(&b), "-o", path_str(&map)], &map, "--poses");
}

#[test]
fn a_poses_file_with_a_bad_line_is_refused_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read_to_string(sequence("poses_kitti.txt")).unwrap();
    let mut lines: Vec<&str> = good.lines().collect();
    lines[1] = "1 0 0 0.25 0 1 0 0 0 0 1";
    let poses = dir.path().join("poses.txt");
    std::fs::write(&poses, lines.join("\n")).unwrap();
    let (a, b) = (sequence("scan00.bin"), sequence("scan01.bin"));
    let map = dir.path().join("x.patches");
    let args = ["prep", path_str(&a), path_str(&b), "--poses", path_str(&poses), "-o", path_str(&map)];
    let stderr = assert_refused(dir.path(), &args, &map, "line 2");
    assert!(stderr.contains("11 numbers"), "{stderr}");
}

#[test]
fn a_re_simulated_sweep_not_named_bin_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (sweep, poses) = (sequence("scan01.bin"), sequence("poses_kitti.txt"));
    // The name is checked before the map is read, so any file stands in for one here.
    let map = dir.path().join("map.patches");
    std::fs::write(&map, b"not a patch store").unwrap();
    let output = dir.path().join("out.ply");
    let args = ["scan", path_str(&map), "--rays-from", path_str(&sweep), "--poses", path_str(&poses)];
    assert_refused(dir.path(), &[&args[..], &["-o", path_str(&output)]].concat(), &output, "*.bin");
}
