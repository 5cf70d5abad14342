//! `sample --tile I --of N`: a stand-in sampled as separate jobs, each writing its part;
//! the parts in order hold exactly the whole sample's points, and `sample --join` makes of
//! them the whole sample's file.

use std::path::Path;

use pointray_test_support::data_file;

use crate::common::pointray_in;

fn positions(path: &Path) -> Vec<glam::DVec3> {
    pointray_io::formats::read_point_cloud(path).expect("the written part reads back").positions
}

#[test]
fn parts_in_order_are_the_whole_sample() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = data_file("meshes/bunny.ply");
    let mesh = mesh.to_str().unwrap();
    let (ok, _, stderr) = pointray_in(dir.path(), &["sample", mesh, "-o", "whole.ply", "--count", "100001"]);
    assert!(ok, "{stderr}");
    let mut joined = Vec::new();
    for part in 0..3 {
        let (name, tile) = (format!("part{part}.ply"), part.to_string());
        let args = ["sample", mesh, "-o", &name, "--count", "100001", "--tile", &tile, "--of", "3"];
        let (ok, stdout, stderr) = pointray_in(dir.path(), &args);
        assert!(ok && stdout.contains(&format!("part {part} of 3")), "{stdout}{stderr}");
        joined.extend(positions(&dir.path().join(name)));
    }
    assert_eq!(joined, positions(&dir.path().join("whole.ply")));
    let (ok, stdout, stderr) = pointray_in(
        dir.path(),
        &["sample", "--join", "part0.ply", "part1.ply", "part2.ply", "-o", "joined.ply"],
    );
    assert!(ok && stdout.contains("100001 points"), "{stdout}{stderr}");
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert!(read("joined.ply") == read("whole.ply"), "the joined parts differ from the whole sample's file");
}

#[test]
fn a_part_outside_the_cut_or_of_blue_noise_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = data_file("meshes/bunny.ply");
    let mesh = mesh.to_str().unwrap();
    let refusals = [
        (vec!["--count", "100", "--tile", "3", "--of", "3"], "is not one of --of 3"),
        (vec!["--count", "2", "--tile", "0", "--of", "3"], "leaves parts empty"),
        (vec!["--count", "100", "--tile", "0", "--of", "2", "--blue-noise"], "--blue-noise"),
    ];
    for (flags, problem) in refusals {
        let args: Vec<&str> = ["sample", mesh, "-o", "part.ply"].into_iter().chain(flags).collect();
        let (ok, _, stderr) = pointray_in(dir.path(), &args);
        assert!(!ok && stderr.contains(problem), "{args:?}: {stderr}");
        assert!(!dir.path().join("part.ply").exists());
    }
}

#[test]
fn a_join_of_a_file_no_sample_wrote_names_it_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = data_file("meshes/bunny.ply");
    let (ok, _, stderr) =
        pointray_in(dir.path(), &["sample", mesh.to_str().unwrap(), "-o", "part.ply", "--count", "10"]);
    assert!(ok, "{stderr}");
    let whole = std::fs::read(dir.path().join("part.ply")).unwrap();
    std::fs::write(dir.path().join("cut.ply"), &whole[..whole.len() - 1]).unwrap();
    std::fs::write(dir.path().join("text.ply"), "ply\nformat ascii 1.0\nelement vertex 0\nend_header\n")
        .unwrap();
    for (bad, problem) in [("cut.ply", "do not hold its 10 vertices"), ("text.ply", "binary little-endian")] {
        let (ok, _, stderr) =
            pointray_in(dir.path(), &["sample", "--join", "part.ply", bad, "-o", "joined.ply"]);
        assert!(!ok && stderr.contains(bad) && stderr.contains(problem), "{bad}: {stderr}");
        assert!(!dir.path().join("joined.ply").exists());
    }
}
