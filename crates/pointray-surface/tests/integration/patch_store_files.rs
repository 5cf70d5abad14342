//! The patch store: bit-identical round trips and a distinct error for each kind of
//! damage.

use crate::common;

use std::path::{Path, PathBuf};

use glam::DVec3;
use pointray_kernels::COLOR_NEIGHBORS;
use pointray_patches::patch_store::{self, StoreError};
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

#[test]
fn round_trip_is_bit_identical() {
    let directory = tempfile::tempdir().unwrap();
    for box_kind in [BoxKind::Cube, BoxKind::Tight] {
        let patches = sample_patches(box_kind);
        let path = written(directory.path(), &patches);
        let loaded = patch_store::read(&path).expect("reading what was written");
        assert_eq!(loaded.settings, patches.settings);
        assert_eq!(loaded.offset.to_array().map(f64::to_bits), patches.offset.to_array().map(f64::to_bits));
        let bytes = |p: &PatchSet| {
            let mut all: Vec<u8> = bytemuck::cast_slice(&p.aabbs).to_vec();
            all.extend_from_slice(bytemuck::cast_slice(&p.hot));
            all.extend_from_slice(bytemuck::cast_slice(&p.cold));
            all.extend_from_slice(bytemuck::cast_slice(&p.color_neighbors));
            all
        };
        assert_eq!(bytes(&loaded), bytes(&patches));
        assert_eq!(loaded.len(), 3000);
        assert_eq!(
            loaded.color_neighbors.len(),
            3000 * COLOR_NEIGHBORS,
            "a coloured cloud keeps its neighbours"
        );
    }
    let leftovers = std::fs::read_dir(directory.path()).unwrap().count();
    assert_eq!(leftovers, 1, "no temporary files left behind");
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
    assert_eq!(patch_store::read(&written(directory.path(), &patches)).unwrap(), patches);
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
    // The last neighbour entry sits just before the checksum; point it past the end so that
    // only the range check can catch it.
    let (path, _, _dir) = resealed_store(|bytes| {
        let last = bytes.len() - 8;
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
fn a_read_store_is_mapped_and_outlives_a_new_store_written_over_it() {
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
    assert_eq!(sections, [true; 4], "a store's sections are mapped, not copied into memory");
    patch_store::write(&path, &tight).unwrap();
    assert_eq!(loaded, cubes, "a store written over a mapped one leaves the mapped one whole");
    assert_eq!(patch_store::read(&path).unwrap(), tight);
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
    // Version 5 stores (whose hot records were 36 bytes) are refused with the way out.
    let (path, error, _dir) = damaged(|bytes| bytes[8..12].copy_from_slice(&5u32.to_le_bytes()));
    assert!(matches!(error, StoreError::WrongVersion { found: 5, .. }), "{error:?}");
    let message = error.to_string();
    assert!(
        message.contains("version 5, this build reads versions 6 and 7: re-run `pointray prep`"),
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

#[test]
fn version_6_stores_still_read() {
    let (path, patches, _dir) = resealed_store(|bytes| bytes[8..12].copy_from_slice(&6u32.to_le_bytes()));
    assert_eq!(patch_store::read(&path).unwrap(), patches);
}

/// `bytes` with `room` zero bytes between the boxes and the hot records, the later
/// sections' offsets moved by as much.
fn with_room(bytes: &mut Vec<u8>, room: usize) {
    let entry =
        |bytes: &[u8], i: usize| u64::from_le_bytes(bytes[72 + 16 * i..80 + 16 * i].try_into().unwrap());
    let hot = entry(bytes, 1) as usize;
    bytes.splice(hot..hot, std::iter::repeat_n(0u8, room));
    for i in 1..4 {
        let moved = entry(bytes, i) + room as u64;
        bytes[72 + 16 * i..80 + 16 * i].copy_from_slice(&moved.to_le_bytes());
    }
}

#[test]
fn room_between_sections_is_read_in_version_7_only() {
    let (path, patches, _dir) = resealed_store(|bytes| with_room(bytes, 4096));
    assert_eq!(patch_store::read(&path).unwrap(), patches);
    let (_, error, _dir) = damaged(|bytes| {
        bytes[8..12].copy_from_slice(&6u32.to_le_bytes());
        with_room(bytes, 16);
        resealed(bytes);
    });
    assert!(error.to_string().contains("a version 6 store leaves no room between its sections"), "{error}");
}

#[test]
fn section_tables_out_of_order_or_misaligned_are_malformed() {
    // The table's entries: (offset, length) at 72 + 16 i.
    let entry =
        |bytes: &[u8], i: usize| u64::from_le_bytes(bytes[72 + 16 * i..80 + 16 * i].try_into().unwrap());
    let damages: [fn(&mut Vec<u8>, u64, u64); 3] = [
        |bytes, boxes, _| bytes[88..96].copy_from_slice(&boxes.to_le_bytes()), // hot over the boxes
        |bytes, _, hot| bytes[88..96].copy_from_slice(&(hot + 4).to_le_bytes()), // misaligned
        |bytes, _, _| bytes[80..88].copy_from_slice(&7u64.to_le_bytes()),      // boxes cut short
    ];
    for damage in damages {
        let (_, error, _dir) = damaged(|bytes| {
            let (boxes, hot) = (entry(bytes, 0), entry(bytes, 1));
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

/// A change to a patch set that its store must not survive.
type Damage = fn(&mut PatchSet);

#[test]
fn numbers_no_renderer_can_build_on_are_malformed_despite_a_good_checksum() {
    let directory = tempfile::tempdir().unwrap();
    let good = sample_patches(BoxKind::Tight);
    let damages: [(&str, Damage); 5] = [
        ("box 7", |p| p.aabbs[7].max[0] = f32::NAN),
        ("box 0", |p| {
            p.aabbs[0] = pointray_kernels::Aabb::new(glam::Vec3::splat(-1e38), glam::Vec3::splat(1e38))
        }),
        ("offset", |p| p.offset.y = f64::NAN),
        ("patch 3", |p| p.hot[3].coefficients[1] = 0x7c00_7c00), // two half-float infinities
        ("cold record 5", |p| p.cold[5].color_reach = f32::NAN),
    ];
    for (expected, damage) in damages {
        let mut patches = good.clone();
        damage(&mut patches);
        let error = patch_store::read(&written(directory.path(), &patches)).unwrap_err();
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
