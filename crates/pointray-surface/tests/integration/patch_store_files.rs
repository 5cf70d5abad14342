//! The patch store: round trips within the compact records' bounds (bit-identical for the
//! full records tile files embed) and a distinct error for each kind of damage.

use crate::common;

use std::path::{Path, PathBuf};

use glam::DVec3;
use pointray_kernels::COLOR_NEIGHBORS;
use pointray_patches::coarse_level::CoarseLevel;
use pointray_patches::patch_store::{self, Encoding, StoreError};
use pointray_patches::{BoxKind, OutlierFilter, PatchSet, PrepSettings, RadiusMode, ScanMode};
use pointray_surface::{NoProgress, prep};

fn sample_patches(box_kind: BoxKind) -> PatchSet {
    let mut cloud = common::sphere(3000, 1.5, DVec3::new(1e5, 2e5, -3.0));
    cloud.colors = Some((0..3000).map(|i| [(i % 256) as u8, 7, 200]).collect());
    cloud.intensities = Some((0..3000).map(|i| i as f32 / 3000.0).collect());
    let settings = PrepSettings { boxes: box_kind, ..PrepSettings::default() };
    prep(&cloud, &settings, &NoProgress).expect("a sphere preps").0
}

fn written(directory: &Path, patches: &PatchSet) -> PathBuf {
    let path = directory.join("model.patches");
    patch_store::write(&path, patches).expect("writing to a temporary directory");
    path
}

/// The section table's entry `i`: (offset, length).
fn entry(bytes: &[u8], i: usize) -> (usize, usize) {
    let word = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap()) as usize;
    (word(72 + 16 * i), word(80 + 16 * i))
}

#[test]
fn round_trip_keeps_every_record_within_the_compact_bounds() {
    let directory = tempfile::tempdir().unwrap();
    for box_kind in [BoxKind::Cube, BoxKind::Tight] {
        let patches = sample_patches(box_kind);
        let path = written(directory.path(), &patches);
        let loaded = patch_store::read(&path).expect("reading what was written");
        assert_eq!(loaded.settings, patches.settings);
        assert_eq!(loaded.offset.to_array().map(f64::to_bits), patches.offset.to_array().map(f64::to_bits));
        assert_eq!(loaded.len(), 3000);
        crate::compact_store::assert_within_compact_bounds(&patches, &loaded);
        assert_eq!(loaded.color_neighbors, patches.color_neighbors, "a coloured cloud keeps its neighbours");
        for (hot, aabb) in loaded.hot.iter().zip(loaded.aabbs.iter()) {
            assert_eq!(
                *aabb,
                pointray_patches::patch_bounds::patch_box(hot, box_kind),
                "boxes are made again"
            );
        }
    }
    let leftovers = std::fs::read_dir(directory.path()).unwrap().count();
    assert_eq!(leftovers, 1, "no temporary files left behind");
}

#[test]
fn the_stored_coarse_level_is_the_one_made_from_the_stored_patches() {
    let directory = tempfile::tempdir().unwrap();
    let patches = sample_patches(BoxKind::Tight);
    let loaded = patch_store::read(&written(directory.path(), &patches)).unwrap();
    let stored = loaded.coarse.as_deref().expect("a compact store holds its coarse level");
    let made = CoarseLevel::of(&loaded);
    assert_eq!(*stored, made);
    assert_eq!(stored.patches.aabbs, made.patches.aabbs);
    assert_eq!(stored.covering(0..loaded.len()), 0..made.patches.len());
    assert!((100..400).contains(&stored.patches.len()), "{} coarse patches", stored.patches.len());
    let info = patch_store::describe(&written(directory.path(), &patches)).unwrap();
    assert_eq!(info.coarse_patches, made.patches.len() as u64);
    assert!(patch_store::as_stored(&patches, Path::new("model")).unwrap().coarse.is_none());
}

#[test]
fn a_damaged_coarse_level_is_refused() {
    let (_, error, _dir) = damaged(|bytes| {
        let at = entry(bytes, 5).0 + 44 + 12;
        bytes[at] ^= 0x10;
    });
    assert!(matches!(error, StoreError::ChecksumMismatch { .. }), "{error:?}");
    let damages: [(&str, Damage); 2] = [
        ("the coarse level: ", |b| {
            let at = entry(b, 5).0 + 44 + 12; // the second coarse patch's radius
            b[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes())
        }),
        ("the coarse level's block counts do not add up to its patches", |b| {
            let at = entry(b, 4).0;
            let count = u32::from_le_bytes(b[at..at + 4].try_into().unwrap());
            b[at..at + 4].copy_from_slice(&(count + 1).to_le_bytes())
        }),
    ];
    for (expected, damage) in damages {
        let (path, _, _dir) = resealed_store(damage);
        let error = patch_store::read(&path).unwrap_err();
        assert!(matches!(error, StoreError::Malformed { .. }), "{expected}: {error:?}");
        let message = error.to_string();
        assert!(message.contains(expected) && message.contains(&path.display().to_string()), "{message}");
    }
}

#[test]
fn the_full_records_round_trip_bit_identical() {
    let patches = sample_patches(BoxKind::Tight);
    let mut bytes = Vec::new();
    let path = Path::new("tile.patches");
    patch_store::write_to(&mut bytes, &patches, Encoding::Full, path).unwrap();
    assert_eq!(patch_store::read_from(&bytes, path).unwrap(), patches);
}

#[test]
fn the_stored_patches_are_those_a_store_gives_and_a_second_round_trip_keeps_them() {
    let directory = tempfile::tempdir().unwrap();
    let patches = sample_patches(BoxKind::Tight);
    let stored = patch_store::as_stored(&patches, Path::new("sphere")).unwrap();
    assert_eq!(stored, patch_store::read(&written(directory.path(), &patches)).unwrap());
    let first_bytes = std::fs::read(written(directory.path(), &patches)).unwrap();
    let again = written(directory.path(), &stored);
    assert!(std::fs::read(&again).unwrap() == first_bytes, "a store of stored patches has the same bytes");
    assert_eq!(patch_store::read(&again).unwrap(), stored);
    assert_eq!(patch_store::as_stored(&stored, Path::new("sphere")).unwrap(), stored);
}

#[test]
fn a_set_no_renderer_can_build_on_is_not_written() {
    let directory = tempfile::tempdir().unwrap();
    let mut patches = sample_patches(BoxKind::Cube);
    patches.aabbs[7].max[0] = f32::NAN;
    let error = patch_store::write(&directory.path().join("bad.patches"), &patches).unwrap_err();
    assert!(matches!(error, StoreError::InconsistentPatchSet { .. }), "{error:?}");
    assert!(error.to_string().contains("box 7"), "{error}");
}

#[test]
fn every_setting_prep_ran_with_is_recorded() {
    let directory = tempfile::tempdir().unwrap();
    let cloud = common::sphere(500, 1.0, DVec3::ZERO);
    let settings = PrepSettings {
        k: 7,
        normal_k: 12,
        recompute_normals: true,
        sensor: Some(DVec3::new(0.5, -2.0, 1e6)),
        remove_outliers: Some(OutlierFilter { neighbors: 8, sigmas: 2.5 }),
        radius: RadiusMode::Adaptive,
        disk_scale: 0.8,
        boxes: BoxKind::Cube,
        scan: ScanMode::Off,
        duplicate_tolerance: 2e-6,
    };
    let patches = prep(&cloud, &settings, &NoProgress).unwrap().0;
    assert_eq!(patches.settings, settings);
    let loaded = patch_store::read(&written(directory.path(), &patches)).unwrap();
    assert_eq!(loaded.settings, settings);
    let defaults = prep(&cloud, &PrepSettings::default(), &NoProgress).unwrap().0;
    let loaded = patch_store::read(&written(directory.path(), &defaults)).unwrap();
    assert_eq!(loaded.settings, PrepSettings::default(), "no sensor and no filter stay absent");
}

#[test]
fn a_cloud_without_colours_or_intensities_stores_no_neighbours() {
    let directory = tempfile::tempdir().unwrap();
    let mut cloud = common::sphere(500, 1.0, DVec3::ZERO);
    let patches = prep(&cloud, &PrepSettings::default(), &NoProgress).unwrap().0;
    assert!(patches.color_neighbors.is_empty());
    // Intensities alone keep them: an intensity ramp colours the points at load.
    cloud.intensities = Some(vec![0.5; 500]);
    let ramped = prep(&cloud, &PrepSettings::default(), &NoProgress).unwrap().0;
    assert_eq!(ramped.color_neighbors.len(), 500 * COLOR_NEIGHBORS);
    let coloured = sample_patches(BoxKind::Cube);
    let neighbour_bytes = 4 * COLOR_NEIGHBORS as u64 * coloured.len() as u64;
    let size = |p: &PatchSet| std::fs::metadata(written(directory.path(), p)).unwrap().len();
    let plain = PatchSet { color_neighbors: Default::default(), ..coloured.clone() };
    assert_eq!(size(&coloured) - size(&plain), neighbour_bytes);
    // 28 bytes a compact record, and the coarse level's 44 bytes for about one patch in 16.
    let uncoloured = size(&patches);
    assert!(
        uncoloured <= 32 * patches.len() as u64 + 1024,
        "{uncoloured} bytes for {} patches",
        patches.len()
    );
    let loaded = patch_store::read(&written(directory.path(), &patches)).unwrap();
    assert!(loaded.color_neighbors.is_empty() && loaded.len() == patches.len());
    assert!(loaded.cold.iter().all(|c| c.color_rgba8 == u32::MAX && c.intensity == 0.0));
}

#[test]
fn a_neighbour_list_of_the_wrong_length_is_not_written() {
    let directory = tempfile::tempdir().unwrap();
    let mut patches = sample_patches(BoxKind::Cube);
    patches.color_neighbors.to_mut().pop();
    let path = directory.path().join("model.patches");
    let error = patch_store::write(&path, &patches).unwrap_err();
    assert!(matches!(error, StoreError::InconsistentPatchSet { .. }), "{error:?}");
    assert!(!path.exists());
}

#[test]
fn a_neighbour_beyond_the_patches_is_malformed() {
    // Point the last neighbour entry past the end so that only the range check can catch it.
    let (path, _, _dir) = resealed_store(|bytes| {
        let (offset, length) = entry(bytes, 3);
        let last = offset + length - 4;
        bytes[last..last + 4].copy_from_slice(&3000u32.to_le_bytes());
    });
    let error = patch_store::read(&path).unwrap_err();
    assert!(matches!(error, StoreError::Malformed { .. }), "{error:?}");
    assert!(
        error
            .to_string()
            .contains(&format!("colour neighbour {} of patch 2999 is 3000", COLOR_NEIGHBORS - 1)),
        "{error}"
    );
}

#[test]
fn a_read_stores_neighbours_are_mapped_and_outlive_a_new_store_written_over_it() {
    let directory = tempfile::tempdir().unwrap();
    let (cubes, tight) = (sample_patches(BoxKind::Cube), sample_patches(BoxKind::Tight));
    let path = written(directory.path(), &cubes);
    let loaded = patch_store::read(&path).unwrap();
    let sections = [
        loaded.aabbs.is_mapped(),
        loaded.hot.is_mapped(),
        loaded.cold.is_mapped(),
        loaded.color_neighbors.is_mapped(),
    ];
    assert_eq!(sections, [false, false, false, true], "decoded records are the process's, neighbours mapped");
    let decoded_again = patch_store::read(&path).unwrap();
    patch_store::write(&path, &tight).unwrap();
    assert_eq!(loaded, decoded_again, "a store written over a mapped one leaves the mapped one whole");
    assert_eq!(loaded.color_neighbors, cubes.color_neighbors);
    assert_eq!(patch_store::read(&path).unwrap().settings.boxes, BoxKind::Tight);
}

#[test]
fn empty_patch_set_round_trips() {
    let directory = tempfile::tempdir().unwrap();
    let empty = PatchSet::default();
    let loaded = patch_store::read(&written(directory.path(), &empty)).unwrap();
    assert_eq!(loaded, empty);
}

fn damaged(damage: impl FnOnce(&mut Vec<u8>)) -> (PathBuf, StoreError, tempfile::TempDir) {
    let directory = tempfile::tempdir().unwrap();
    let path = written(directory.path(), &sample_patches(BoxKind::Cube));
    let mut bytes = std::fs::read(&path).unwrap();
    damage(&mut bytes);
    std::fs::write(&path, bytes).unwrap();
    let error = patch_store::read(&path).expect_err("damaged stores are refused");
    (path, error, directory)
}

#[test]
fn another_version_is_refused_by_name() {
    // Version 8 stores (without the coarse level) are refused with the way out.
    let (path, error, _dir) = damaged(|bytes| bytes[8..12].copy_from_slice(&8u32.to_le_bytes()));
    assert!(matches!(error, StoreError::WrongVersion { found: 8, .. }), "{error:?}");
    let message = error.to_string();
    assert!(
        message.contains("patch store version 8, this build reads version 9 only: re-run `pointray prep`"),
        "{message}"
    );
    assert!(message.contains(&path.display().to_string()), "{message}");
}

/// A store of the sample patches changed by `change` and given the checksum of its new bytes,
/// so that only the other checks can refuse it.
fn resealed_store(change: impl FnOnce(&mut Vec<u8>)) -> (PathBuf, PatchSet, tempfile::TempDir) {
    let directory = tempfile::tempdir().unwrap();
    let patches = sample_patches(BoxKind::Cube);
    let path = written(directory.path(), &patches);
    let mut bytes = std::fs::read(&path).unwrap();
    change(&mut bytes);
    resealed(&mut bytes);
    std::fs::write(&path, bytes).unwrap();
    (path, patches, directory)
}

/// `bytes` with their checksum recomputed.
fn resealed(bytes: &mut [u8]) {
    let body = bytes.len() - 4;
    let checksum = crc32fast::hash(&bytes[..body]);
    bytes[body..].copy_from_slice(&checksum.to_le_bytes());
}

/// `bytes` with `room` zero bytes between the block frames and the patches, the later
/// sections' offsets moved by as much.
fn with_room(bytes: &mut Vec<u8>, room: usize) {
    let patches = entry(bytes, 1).0;
    bytes.splice(patches..patches, std::iter::repeat_n(0u8, room));
    for i in 1..6 {
        let moved = (entry(bytes, i).0 + room) as u64;
        bytes[72 + 16 * i..80 + 16 * i].copy_from_slice(&moved.to_le_bytes());
    }
}

#[test]
fn room_between_sections_is_read() {
    let directory = tempfile::tempdir().unwrap();
    let expected = patch_store::read(&written(directory.path(), &sample_patches(BoxKind::Cube))).unwrap();
    let (path, _, _dir) = resealed_store(|bytes| with_room(bytes, 4096));
    assert_eq!(patch_store::read(&path).unwrap(), expected);
}

#[test]
fn section_tables_out_of_order_or_misaligned_are_malformed() {
    let damages: [fn(&mut Vec<u8>, u64, u64); 3] = [
        |bytes, boxes, _| bytes[88..96].copy_from_slice(&boxes.to_le_bytes()), // hot over the boxes
        |bytes, _, hot| bytes[88..96].copy_from_slice(&(hot + 4).to_le_bytes()), // misaligned
        |bytes, _, _| bytes[80..88].copy_from_slice(&7u64.to_le_bytes()),      // boxes cut short
    ];
    for damage in damages {
        let (_, error, _dir) = damaged(|bytes| {
            let (boxes, hot) = (entry(bytes, 0).0 as u64, entry(bytes, 1).0 as u64);
            damage(bytes, boxes, hot);
            resealed(bytes);
        });
        assert!(matches!(error, StoreError::Malformed { .. }), "{error:?}");
        assert!(error.to_string().contains("section table"), "{error}");
    }
}

#[test]
fn a_flipped_byte_is_a_checksum_mismatch() {
    for position in [200, 100_000, 150_000] {
        let (path, error, _dir) = damaged(|bytes| bytes[position] ^= 0x10);
        assert!(matches!(error, StoreError::ChecksumMismatch { .. }), "byte {position}: {error:?}");
        let message = error.to_string();
        assert!(message.contains("corrupted: checksum mismatch"), "{message}");
        assert!(message.contains(&path.display().to_string()), "{message}");
    }
}

#[test]
fn a_truncated_file_is_refused() {
    let (_, error, _dir) = damaged(|bytes| bytes.truncate(bytes.len() - 100));
    assert!(matches!(error, StoreError::WrongLength { .. }), "{error:?}");
    assert!(error.to_string().contains("truncated"));
    let (_, error, _dir) = damaged(|bytes| bytes.truncate(20));
    assert!(matches!(error, StoreError::WrongLength { .. }), "{error:?}");
}

#[test]
fn other_files_are_not_patch_stores() {
    let (_, error, _dir) = damaged(|bytes| bytes[0] = b'X');
    assert!(matches!(error, StoreError::NotAPatchStore { .. }), "{error:?}");
    let directory = tempfile::tempdir().unwrap();
    let ply = directory.path().join("cloud.ply");
    std::fs::write(&ply, b"ply\nformat ascii 1.0\n").unwrap();
    assert!(matches!(patch_store::read(&ply), Err(StoreError::NotAPatchStore { .. })));
    let missing = patch_store::read(&directory.path().join("missing.patches")).unwrap_err();
    assert!(matches!(missing, StoreError::Io { .. }));
}

/// A change to a store's bytes that its checksum, made again, does not catch.
type Damage = fn(&mut Vec<u8>);

/// Where `field` of compact patch `i` lies: position (8 bytes), frame, aspect and c1, c2..c5
/// (8), radii (4).
fn patch_field(bytes: &[u8], i: usize, field: usize) -> usize {
    entry(bytes, 1).0 + 28 * i + field
}

#[test]
fn numbers_no_renderer_can_build_on_are_malformed_despite_a_good_checksum() {
    let damages: [(&str, Damage); 5] = [
        ("a block's box is not finite", |b| {
            let at = entry(b, 0).0 + 4;
            b[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes())
        }),
        ("a block's radius scale is out of range", |b| {
            let at = entry(b, 0).0 + 24;
            b[at..at + 4].copy_from_slice(&900i32.to_le_bytes())
        }),
        ("offset", |b| b[32..40].copy_from_slice(&f64::NAN.to_le_bytes())),
        ("patch 3", |b| {
            let at = patch_field(b, 3, 16);
            b[at..at + 4].copy_from_slice(&0x7c00_7c00u32.to_le_bytes()) // two half-float infinities
        }),
        ("cold record 5", |b| {
            let at = patch_field(b, 5, 26);
            b[at..at + 2].copy_from_slice(&0x7e00u16.to_le_bytes()) // a half-float NaN reach
        }),
    ];
    for (expected, damage) in damages {
        let (path, _, _dir) = resealed_store(damage);
        let error = patch_store::read(&path).unwrap_err();
        assert!(matches!(error, StoreError::Malformed { .. }), "{expected}: {error:?}");
        assert!(error.to_string().contains(expected), "{expected}: {error}");
    }
}

#[cfg(unix)]
#[test]
fn stores_are_written_with_the_usual_permissions_not_0600() {
    use std::os::unix::fs::PermissionsExt;
    let directory = tempfile::tempdir().unwrap();
    let store = written(directory.path(), &PatchSet::default());
    let reference = directory.path().join("reference");
    std::fs::write(&reference, b"x").unwrap();
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&store), mode(&reference) & 0o644, "0644 less the umask, like any output");
}
