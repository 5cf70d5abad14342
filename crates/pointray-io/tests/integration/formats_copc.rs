//! COPC reader: the Autzen tile written as COPC by copclib (`data/scans/write_autzen_copc.py`)
//! reads as the LAS it came from, its parallel read agrees with a sequential LAZ read, and
//! corrupt hierarchies and chunks are refused with the file named.

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use pointray_io::formats::las::{read_las, read_las_from};
use pointray_io::{IoError, PointCloud};

/// The first VLR's data (the COPC info) starts after the 375-byte header and 54-byte VLR
/// header; the root hierarchy page's offset and size are 40 bytes into it.
const ROOT_PAGE_OFFSET_AT: usize = 375 + 54 + 40;
const ENTRY_BYTES: usize = 32;
const EVLR_START_AT: usize = 235;

fn copc_path() -> PathBuf {
    pointray_test_support::data_file("scans/autzen_trim.copc.laz")
}

/// Each point's position, colour, intensity and class, sorted, so that clouds compare up to
/// point order.
fn sorted_points(cloud: &PointCloud) -> Vec<String> {
    let colors = cloud.colors.as_ref().expect("colours");
    let intensities = cloud.intensities.as_ref().expect("intensities");
    let classes = cloud.classifications.as_ref().expect("classes");
    let mut points: Vec<String> = (0..cloud.len())
        .map(|i| format!("{} {:?} {} {}", cloud.positions[i], colors[i], intensities[i], classes[i]))
        .collect();
    points.sort_unstable();
    points
}

#[test]
fn copc_tile_reads_as_the_las_it_was_written_from() {
    let las = read_las(&pointray_test_support::data_file("scans/autzen_trim.las")).unwrap();
    let copc = read_las(&copc_path()).unwrap();
    assert_eq!(copc.len(), 110_000);
    assert_eq!(sorted_points(&copc), sorted_points(&las));
}

#[test]
fn parallel_chunk_read_matches_a_sequential_laz_read() {
    let path = copc_path();
    let sequential = read_las_from(BufReader::new(File::open(&path).unwrap()), &path).unwrap();
    assert_eq!(read_las(&path).unwrap(), sequential);
}

// ---- corrupt files ----

fn u64_at(bytes: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap())
}

/// Writes `value` as the little-endian u64 at byte `at`.
fn set_u64_at(bytes: &mut [u8], at: usize, value: u64) {
    bytes[at..at + 8].copy_from_slice(&value.to_le_bytes());
}

fn root_page_at(bytes: &[u8]) -> usize {
    u64_at(bytes, ROOT_PAGE_OFFSET_AT) as usize
}

/// The byte of the root page's entry field `field` (16: offset, 24: byte size, 28: point
/// count) of its `index`th entry.
fn entry_field_at(bytes: &[u8], index: usize, field: usize) -> usize {
    root_page_at(bytes) + index * ENTRY_BYTES + field
}

fn refused(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf, IoError) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    let Err(error) = read_las(&path) else { panic!("corrupt COPC {name} was read") };
    (dir, path, error)
}

fn assert_names_file(path: &Path, error: &IoError, needle: &str) {
    let message = error.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    assert!(message.contains(needle), "{message:?} lacks {needle:?}");
}

fn copc_bytes() -> Vec<u8> {
    std::fs::read(copc_path()).unwrap()
}

#[test]
fn truncated_chunk_is_refused() {
    // Cut the last chunk short, keeping the hierarchy EVLR after it.
    let bytes = copc_bytes();
    let evlr_start = u64_at(&bytes, EVLR_START_AT) as usize;
    let cut = 1000;
    let mut truncated = bytes[..evlr_start - cut].to_vec();
    truncated.extend_from_slice(&bytes[evlr_start..]);
    let moved_evlr = (evlr_start - cut) as u64;
    set_u64_at(&mut truncated, EVLR_START_AT, moved_evlr);
    let root = root_page_at(&bytes) - cut;
    set_u64_at(&mut truncated, ROOT_PAGE_OFFSET_AT, root as u64);
    let (_dir, path, error) = refused("cut.copc.laz", &truncated);
    assert_names_file(&path, &error, "outside the point data");
}

#[test]
fn chunk_offset_past_the_file_is_refused() {
    let mut bytes = copc_bytes();
    let at = entry_field_at(&bytes, 0, 16);
    set_u64_at(&mut bytes, at, 1 << 40);
    let (_dir, path, error) = refused("far.copc.laz", &bytes);
    assert_names_file(&path, &error, "outside the point data");
}

#[test]
fn root_page_offset_outside_the_hierarchy_is_refused() {
    let mut bytes = copc_bytes();
    let wrong = (root_page_at(&bytes) + 7) as u64;
    set_u64_at(&mut bytes, ROOT_PAGE_OFFSET_AT, wrong);
    let (_dir, path, error) = refused("root.copc.laz", &bytes);
    assert_names_file(&path, &error, "COPC hierarchy page");
}

/// Makes the root page's `index`th entry a reference, keyed `key` (16 bytes), to the page of
/// `size` bytes at file offset `page`.
fn make_page_reference(bytes: &mut [u8], index: usize, key: &[u8], page: usize, size: usize) {
    let entry = entry_field_at(bytes, index, 0);
    bytes[entry..entry + 16].copy_from_slice(key);
    set_u64_at(bytes, entry + 16, page as u64);
    bytes[entry + 24..entry + 28].copy_from_slice(&(size as i32).to_le_bytes());
    bytes[entry + 28..entry + 32].copy_from_slice(&(-1i32).to_le_bytes());
}

#[test]
fn hierarchy_page_referring_back_to_the_root_is_refused() {
    // Turn a chunk entry into a reference to the root page: a cycle the `las` crate would
    // follow forever.
    let mut bytes = copc_bytes();
    let (root, root_size) = (root_page_at(&bytes), u64_at(&bytes, ROOT_PAGE_OFFSET_AT + 8) as usize);
    let first_chunk_key = bytes[root + ENTRY_BYTES..root + ENTRY_BYTES + 16].to_vec();
    make_page_reference(&mut bytes, 1, &first_chunk_key, root, root_size);
    let (_dir, path, error) = refused("cycle.copc.laz", &bytes);
    assert_names_file(&path, &error, "cycle");
}

#[test]
fn second_page_of_one_node_is_refused() {
    // Turn a chunk entry into a reference, keyed by the root node, to the page's last entry:
    // the `las` crate finds pages by node and would walk the root page again.
    let mut bytes = copc_bytes();
    let root_size = u64_at(&bytes, ROOT_PAGE_OFFSET_AT + 8) as usize;
    let last_entry = root_page_at(&bytes) + root_size - ENTRY_BYTES;
    make_page_reference(&mut bytes, 1, &[0; 16], last_entry, ENTRY_BYTES);
    let (_dir, path, error) = refused("twice.copc.laz", &bytes);
    assert_names_file(&path, &error, "owns another page");
}

#[test]
fn point_count_the_header_does_not_declare_is_refused() {
    let mut bytes = copc_bytes();
    let at = entry_field_at(&bytes, 0, 28);
    let count = i32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    bytes[at..at + 4].copy_from_slice(&(count + 1).to_le_bytes());
    let (_dir, path, error) = refused("count.copc.laz", &bytes);
    assert_names_file(&path, &error, "header declares 110000");
}

#[test]
fn point_count_beyond_what_the_chunk_holds_is_refused_before_decoding() {
    // The decoder would size its buffer by the count first: tens of gigabytes.
    let mut bytes = copc_bytes();
    let at = entry_field_at(&bytes, 0, 28);
    bytes[at..at + 4].copy_from_slice(&i32::MAX.to_le_bytes());
    let (_dir, path, error) = refused("huge.copc.laz", &bytes);
    assert_names_file(&path, &error, "more than LAZ holds");
}

#[test]
fn every_truncation_is_refused_without_a_panic() {
    let bytes = copc_bytes();
    for keep in (0..bytes.len()).step_by(bytes.len() / 37) {
        let (_dir, path, error) = refused("short.copc.laz", &bytes[..keep]);
        assert!(error.to_string().contains(&path.display().to_string()), "{error}");
    }
}
