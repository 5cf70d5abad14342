//! Format detection: content decides over a lying or missing extension.

use std::path::{Path, PathBuf};

use pointray_io::formats::detect::{PointFormat, detect_format, detect_format_from};

fn write_bytes(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    (dir, path)
}

fn las_head(point_format: u8) -> Vec<u8> {
    let mut head = vec![0u8; 227];
    head[..4].copy_from_slice(b"LASF");
    head[104] = point_format;
    head
}

#[test]
fn signatures_win_over_extensions() {
    let cases: [(&[u8], PointFormat); 5] = [
        (&las_head(3), PointFormat::Las),
        (&las_head(3 | 0x80), PointFormat::Laz),
        (b"ASTM-E57\x00\x00", PointFormat::E57),
        (b"ply\nformat ascii 1.0\n", PointFormat::Ply),
        (b"# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n", PointFormat::Pcd),
    ];
    for (head, expected) in cases {
        assert_eq!(detect_format_from(head, Path::new("cloud.xyz")), Some(expected));
        assert_eq!(detect_format_from(head, Path::new("no_extension")), Some(expected));
    }
}

#[test]
fn pcd_without_the_pcl_comment_is_detected_by_version_and_fields() {
    let head = b"VERSION .7\nFIELDS x y z\nSIZE 4 4 4\n";
    assert_eq!(detect_format_from(head, Path::new("cloud.txt")), Some(PointFormat::Pcd));
}

#[test]
fn text_without_a_signature_is_xyz() {
    assert_eq!(detect_format_from(b"x,y,z\n1,2,3\n", Path::new("cloud.bin")), Some(PointFormat::Xyz));
    // A multi-byte character cut at the end of the head is still text.
    assert_eq!(
        detect_format_from("1 2 3 é".as_bytes().split_last().unwrap().1, Path::new("a")),
        Some(PointFormat::Xyz)
    );
}

#[test]
fn binary_without_a_signature_goes_by_extension() {
    let binary = [0u8, 1, 2, 3, 0xff, 0x80, 0x00, 0x10];
    assert_eq!(detect_format_from(&binary, Path::new("000001.BIN")), Some(PointFormat::RawBin));
    assert_eq!(detect_format_from(&binary, Path::new("cloud.dat")), None);
}

#[test]
fn unknown_binary_file_is_unsupported_and_lists_formats() {
    let (_dir, path) = write_bytes("mystery.dat", &[0u8, 159, 146, 150]);
    let message = detect_format(&path).unwrap_err().to_string();
    assert!(message.contains("mystery.dat") && message.contains("supported: LAS/LAZ"), "{message}");
}

#[test]
fn empty_file_is_refused() {
    let (_dir, path) = write_bytes("empty.las", &[]);
    assert!(detect_format(&path).unwrap_err().to_string().contains("empty"));
}
