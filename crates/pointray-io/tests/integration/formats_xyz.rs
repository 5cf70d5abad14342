//! Text point reader: layouts by column count, header lines, column specs, PTS count lines,
//! and malformed files.

use std::path::PathBuf;

use glam::{DVec3, Vec3};
use pointray_io::formats::columns::{ColumnSpec, ColumnSpecError};
use pointray_io::formats::detect::{PointFormat, detect_format};
use pointray_io::formats::xyz::read_xyz;
use pointray_io::{IoError, PointCloud};

fn write_file(name: &str, text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

fn read_text(name: &str, text: &str, spec: Option<&ColumnSpec>) -> PointCloud {
    let (_dir, path) = write_file(name, text);
    read_xyz(&path, spec).unwrap()
}

/// Points far from the origin with fractional parts a float32 could not hold.
fn geo_points() -> Vec<DVec3> {
    (0..20)
        .map(|i| DVec3::new(1_234_567.125 + f64::from(i) * 0.01, 7_654_321.5, f64::from(i) * 0.25))
        .collect()
}

#[test]
fn written_positions_and_colours_read_back_exactly() {
    let points = geo_points();
    let text: String = points
        .iter()
        .enumerate()
        .map(|(i, p)| format!("{} {} {} {} {} {}\n", p.x, p.y, p.z, i * 10, 255 - i, 7))
        .collect();
    let cloud = read_text("cloud.xyz", &text, None);
    assert_eq!(cloud.positions, points);
    let colors = cloud.colors.unwrap();
    assert_eq!(colors[3], [30, 252, 7]);
    assert_eq!(cloud.intensities, None);
    assert_eq!(cloud.normals, None);
}

#[test]
fn pts_count_line_is_skipped_and_seven_columns_are_x_y_z_i_r_g_b() {
    let text = "2\n1.5 2.5 3.5 -2047 10 20 30\n4 5 6 2047 40 50 60\n";
    let cloud = read_text("scan.pts", text, None);
    assert_eq!(cloud.positions, vec![DVec3::new(1.5, 2.5, 3.5), DVec3::new(4.0, 5.0, 6.0)]);
    assert_eq!(cloud.colors, Some(vec![[10, 20, 30], [40, 50, 60]]));
    // Leica PTS intensities run from -2048 to 2047: shifted and scaled into [0, 1].
    assert_eq!(cloud.intensities, Some(vec![0.0, 1.0]));
}

#[test]
fn csv_header_names_the_columns_in_any_order() {
    let text = "id,Z,X,Y,Intensity,nx,ny,nz\n0,3,1,2,0.5,0,0,1\n1,6,4,5,0.25,0,1,0\n";
    let cloud = read_text("cloud.csv", text, None);
    assert_eq!(cloud.positions, vec![DVec3::new(1.0, 2.0, 3.0), DVec3::new(4.0, 5.0, 6.0)]);
    assert_eq!(cloud.intensities, Some(vec![0.5, 0.25]));
    assert_eq!(cloud.normals, Some(vec![Vec3::Z, Vec3::Y]));
}

#[test]
fn column_spec_overrides_header_and_count() {
    let spec = ColumnSpec::parse("_, r, g, b, x, y, z").unwrap();
    let text = "a b c d e f g\n9 1 0.5 0 10 20 30\n";
    let cloud = read_text("spec.txt", text, Some(&spec));
    assert_eq!(cloud.positions, vec![DVec3::new(10.0, 20.0, 30.0)]);
    // All colours within [0, 1]: float colours scaled to bytes.
    assert_eq!(cloud.colors, Some(vec![[255, 128, 0]]));
}

#[test]
fn comments_blank_lines_semicolons_and_padding_are_accepted() {
    let expected = vec![DVec3::new(1.0, 2.0, 3.0), DVec3::new(4.0, 5.0, 6.0)];
    let text = "# exported\n\n// more\n1; 2;3\n  4 ;5;6;  \n";
    assert_eq!(read_text("semicolons.txt", text, None).positions, expected);
    assert_eq!(read_text("tabs.txt", "1 2\t3\n  4\t5 6  \n", None).positions, expected);
}

#[test]
fn rings_and_classifications_come_from_a_header_or_a_spec() {
    let cloud = read_text("scan.csv", "x,y,z,ring,classification,time\n1,2,3,7,2,0.5\n", None);
    assert_eq!((cloud.rings, cloud.classifications), (Some(vec![7]), Some(vec![2])));
    let spec = ColumnSpec::parse("x y z intensity ring").unwrap();
    let cloud = read_text("sweep.txt", "1 2 3 0.5 31\n4 5 6 0.25 0\n", Some(&spec));
    assert_eq!(cloud.rings, Some(vec![31, 0]));
    assert_eq!(cloud.intensities, Some(vec![0.5, 0.25]));
}

#[test]
fn text_is_detected_whatever_the_extension() {
    let (_dir, path) = write_file("cloud.dat", "1 2 3\n4 5 6\n");
    assert_eq!(detect_format(&path).unwrap(), PointFormat::Xyz);
}

#[test]
fn bad_column_specs_say_what_is_wrong() {
    assert!(matches!(ColumnSpec::parse("x,y,q"), Err(ColumnSpecError::UnknownName { .. })));
    assert!(matches!(ColumnSpec::parse("x,y"), Err(ColumnSpecError::MissingPosition { .. })));
    assert!(matches!(ColumnSpec::parse("x,y,z,x"), Err(ColumnSpecError::Duplicate { .. })));
    assert!(matches!(ColumnSpec::parse("x,y,z,r,g"), Err(ColumnSpecError::PartialGroup { .. })));
    assert!(ColumnSpec::parse("x,y,z,q").unwrap_err().to_string().contains("\"q\""));
}

// ---- malformed files ----

fn assert_refused(name: &str, bytes: &[u8], needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    let error: IoError = read_xyz(&path, None).expect_err("a malformed file must not read");
    let message = error.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    assert!(message.contains(needle), "{message:?} lacks {needle:?}");
}

#[test]
fn empty_file_is_refused() {
    assert_refused("empty.xyz", b"", "no point lines");
}

#[test]
fn non_numeric_value_names_its_line() {
    assert_refused("word.xyz", b"1 2 3\n4 five 6\n", "line 2");
}

#[test]
fn short_row_names_its_line() {
    assert_refused("short.xyz", b"1 2 3\n4 5\n", "line 2: 2 values, the layout needs 3");
}

#[test]
fn a_switch_from_three_to_six_columns_is_refused() {
    assert_refused(
        "switch.xyz",
        b"1 2 3\n4 5 6\n7 8 9 255 0 0\n",
        "line 3: 6 values, the layout needs 3 (x,y,z)",
    );
}

#[test]
fn mixed_separators_are_refused() {
    assert_refused("mixed.csv", b"1,2,3\n4 5 6\n", "line 2 separates values by whitespace, line 1 by commas");
    assert_refused("inline.csv", b"1,2 3\n", "line 1 mixes commas and whitespace");
    assert_refused("both.csv", b"1,2;3\n", "line 1 mixes commas and semicolons");
    assert_refused("gap.csv", b"1,,2,3\n", "line 1 has an empty value between commas");
}

#[test]
fn a_column_count_without_an_obvious_layout_is_refused() {
    assert_refused("five.xyz", b"1 2 3 0.5 7\n", "5 values per line fit no layout");
    assert_refused("eight.xyz", b"1 2 3 4 5 6 7 8\n", "x,y,z,intensity,ring");
}

#[test]
fn rings_that_are_not_small_whole_numbers_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ring.txt");
    std::fs::write(&path, "1 2 3 1.5\n").unwrap();
    let spec = ColumnSpec::parse("x,y,z,ring").unwrap();
    let message = read_xyz(&path, Some(&spec)).unwrap_err().to_string();
    assert!(message.contains("line 1: ring 1.5 is not a whole number from 0 to 65535"), "{message}");
}

#[test]
fn non_utf8_bytes_are_refused() {
    assert_refused("binary.xyz", &[0x31, 0x20, 0xff, 0xfe, 0x0a], "not UTF-8");
}

#[test]
fn header_without_positions_is_refused() {
    assert_refused("header.csv", b"a,b,c\n1,2,3\n", "needs x, y and z");
}

#[test]
fn infinite_coordinate_is_refused() {
    assert_refused("inf.xyz", b"1 2 3\ninf 0 0\n", "line 2: non-finite");
}

#[test]
fn colour_beyond_sixteen_bits_is_refused() {
    assert_refused("colour.xyz", b"1 2 3 70000 0 0\n", "beyond 16 bits");
}
