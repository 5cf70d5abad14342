//! `prep` over the test files laspy, pypcd4, pye57 and libE57Format ship (`data/peer/`): each makes patches,
//! or is refused in words that name the file and say why, never a panic.

use crate::common::pointray_in;

/// The files prep refuses, and the words that say why.
const REFUSED: &[(&str, &str)] = &[
    ("laspy/unregistered_extra_bytes.las", "lie on one line"),
    ("pypcd4/ascii_empty.pcd", "file is empty"),
    ("pypcd4/ascii_invalid_header.pcd", "before DATA line"),
    ("pypcd4/ascii_with_empty_points.pcd", "0 points"),
    ("pye57/testWithNormals.e57", "2 points"),
    ("libE57Format/InvalidCVHeader.e57", "not a readable E57 file"),
    ("libE57Format/ZeroPoints.e57", "0 points"),
    ("libE57Format/ZeroPointsInvalid.e57", "not a readable E57 file"),
    ("libE57Format/bad-crc.e57", "not a readable E57 file"),
    ("libE57Format/empty.e57", "holds no point cloud"),
];

#[test]
fn every_peer_test_file_preps_or_is_refused_naming_it() {
    let peer = pointray_test_support::data_dir().join("peer");
    let dir = tempfile::tempdir().unwrap();
    let mut files: Vec<_> = ["laspy", "pypcd4", "pye57", "libE57Format"]
        .iter()
        .flat_map(|library| std::fs::read_dir(peer.join(library)).unwrap().flatten())
        .map(|entry| entry.path())
        .filter(|path| !path.file_name().unwrap().to_string_lossy().starts_with("LICENSE"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 23, "{files:?}");
    for file in files {
        let name = file.strip_prefix(&peer).unwrap().to_str().unwrap().to_owned();
        let output = dir.path().join("out.patches");
        let (ok, _, stderr) =
            pointray_in(dir.path(), &["prep", file.to_str().unwrap(), "-o", output.to_str().unwrap()]);
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        match REFUSED.iter().find(|(refused, _)| *refused == name) {
            Some((_, why)) => {
                let file_name = file.file_name().unwrap().to_str().unwrap();
                assert!(!ok && stderr.contains(file_name) && stderr.contains(why), "{name}: {stderr}");
            }
            None => assert!(ok && output.is_file(), "{name}: {stderr}"),
        }
    }
}
