//! The test files that laspy, pypcd4, pye57 and libE57Format ship (`data/peer/`, sources in
//! data/SOURCES.md) read as those libraries read them: the same points, the first and last
//! of them at the same coordinates. `bench/peer_files.py` makes the same comparison over every
//! point file the libraries ship, the large ones too.

use glam::DVec3;
use pointray_io::formats::read_point_cloud;

/// A file, its points, and its first and last point, as the peer library reads them
/// (laspy 2.7.0, pypcd4 1.5.1, pye57 0.4.19 for the E57 files; pypcd4's NaN points left
/// out, as pointray leaves them out).
const AS_PEERS_READ: &[(&str, usize, [f64; 3], [f64; 3])] = &[
    ("laspy/simple.las", 1065, [637012.24, 849028.31, 431.66], [637342.85, 853240.32, 423.92]),
    ("laspy/extra.laz", 1065, [637012.24, 849028.31, 431.66], [637342.85, 853240.32, 423.92]),
    ("laspy/simple.copc.laz", 1065, [636145.6, 849170.47, 428.15], [638314.34, 852793.54, 419.65]),
    (
        "laspy/1_4_w_evlr.laz",
        1000,
        [1694510.3869346841, 1816497.966263977, 5598.3596128149675],
        [1694291.6363326558, 1816493.0662305846, 5597.089652537912],
    ),
    ("laspy/unregistered_extra_bytes.las", 4, [1.0, 1.0, 1.0], [4.0, 4.0, 4.0]),
    ("pypcd4/ascii.pcd", 213, [0.93773, 0.33763, 0.0], [-0.18369, -0.23729, 0.0]),
    ("pypcd4/ascii_with_underscore.pcd", 213, [0.93773, 0.33763, 0.0], [-0.18369, -0.23729, 0.0]),
    ("pypcd4/binary.pcd", 213, [0.93773, 0.33763, 0.0], [-0.18369, -0.23729, 0.0]),
    ("pypcd4/binary_compressed.pcd", 213, [0.93773, 0.33763, 0.0], [-0.18369, -0.23729, 0.0]),
    ("pypcd4/ascii_multi_count.pcd", 8, [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
    ("pypcd4/ascii_organized.pcd", 8, [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
    ("pypcd4/binary_compressed_organized.pcd", 8, [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
    ("pypcd4/ascii_with_empty_points.pcd", 0, [0.0; 3], [0.0; 3]),
    ("pye57/testWithNormals.e57", 2, [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]),
    ("pye57/translationWithoutRotation.e57", 4, [4.0, 5.0, 6.0], [5.0, 6.0, 6.0]),
    (
        "libE57Format/ColouredCubeFloat.e57",
        7680,
        [-0.5, -0.4990559220314026, 0.07136291265487671],
        [0.16827905178070068, -0.00394439697265625, 0.5],
    ),
    ("libE57Format/ZeroPoints.e57", 0, [0.0; 3], [0.0; 3]),
];

/// Files the peer libraries refuse too, and why pointray does. (pye57 reads
/// `InvalidCVHeader.e57` as 0 points; its name and pointray say its header is invalid.)
const REFUSED: &[(&str, &str)] = &[
    ("pypcd4/ascii_empty.pcd", "file is empty"),
    ("pypcd4/ascii_invalid_header.pcd", "before DATA line"),
    ("libE57Format/InvalidCVHeader.e57", "not a readable E57 file"),
    ("libE57Format/ZeroPointsInvalid.e57", "not a readable E57 file"),
    ("libE57Format/bad-crc.e57", "not a readable E57 file"),
    ("libE57Format/empty.e57", "holds no point cloud"),
];

fn peer_file(relative: &str) -> std::path::PathBuf {
    pointray_test_support::data_file(&format!("peer/{relative}"))
}

#[test]
fn the_peer_libraries_test_files_read_as_the_libraries_read_them() {
    for &(name, count, first, last) in AS_PEERS_READ {
        let cloud = read_point_cloud(&peer_file(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(cloud.len(), count, "{name}");
        let (Some(&ours_first), Some(&ours_last)) = (cloud.positions.first(), cloud.positions.last()) else {
            continue;
        };
        for (ours, theirs) in [(ours_first, first), (ours_last, last)] {
            // pypcd4's values are f32 read back; the LAS values are integers times a scale.
            let tolerance = 1e-6 * DVec3::from_array(theirs).abs().max_element().max(1.0);
            let difference = (ours - DVec3::from_array(theirs)).abs().max_element();
            assert!(difference <= tolerance, "{name}: {ours} against the peer's {theirs:?}");
        }
    }
}

#[test]
fn the_files_the_peer_libraries_refuse_are_refused_naming_them() {
    for &(name, why) in REFUSED {
        let error = read_point_cloud(&peer_file(name)).unwrap_err().to_string();
        let file = name.rsplit('/').next().unwrap();
        assert!(error.contains(file) && error.contains(why), "{name}: {error}");
    }
}
