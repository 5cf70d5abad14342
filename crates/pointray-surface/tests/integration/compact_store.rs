//! The compact store's round trip on a model and on a real LiDAR sweep: every record comes
//! back within the bounds `compact_patches` states, and the sweep keeps its positions to a
//! tenth of a millimetre.

use std::path::Path;

use pointray_io::formats::read_point_cloud;
use pointray_kernels::PatchHot;
use pointray_patches::compact_patches::BLOCK_PATCHES;
use pointray_patches::{PatchSet, PrepSettings, ScanStructure, patch_store};
use pointray_surface::{NoProgress, prep};
use pointray_test_support::data_file;

/// The largest error the compact store's quantisation adds to each kind of field.
#[derive(Debug, Default)]
pub struct CompactErrors {
    /// The largest position error, in the cloud's units.
    pub position: f64,
    /// The largest `d_u` error relative to `d_u`.
    pub radius: f64,
}

/// Checks `after` (a store's decoding of `before`) against the bounds of `compact_patches`
/// and returns the largest errors seen. The frame, aspect and coefficients must be `before`'s
/// bits, the colours and neighbours equal.
pub fn assert_within_compact_bounds(before: &PatchSet, after: &PatchSet) -> CompactErrors {
    assert_eq!(after.len(), before.len());
    assert_eq!(after.color_neighbors, before.color_neighbors);
    let mut errors = CompactErrors::default();
    for (block, (hot, decoded)) in
        before.hot.chunks(BLOCK_PATCHES).zip(after.hot.chunks(BLOCK_PATCHES)).enumerate()
    {
        let half_step = half_steps(hot);
        for (i, (a, b)) in hot.iter().zip(decoded).enumerate() {
            let patch = block * BLOCK_PATCHES + i;
            for (axis, half_step) in half_step.iter().enumerate() {
                let error = f64::from((a.origin[axis] - b.origin[axis]).abs());
                let rounding = f64::from(f32::EPSILON * a.origin[axis].abs());
                assert!(error <= half_step + rounding, "patch {patch} axis {axis}: {a:?} {b:?}");
                errors.position = errors.position.max(error);
            }
            let radius = f64::from((a.radius - b.radius).abs() / a.radius);
            assert!(radius <= 2f64.powi(-11), "patch {patch}: radius {} became {}", a.radius, b.radius);
            errors.radius = errors.radius.max(radius);
            assert_eq!((a.frame, a.aspect_c1, a.coefficients), (b.frame, b.aspect_c1, b.coefficients));
        }
    }
    for (i, (a, b)) in before.cold.iter().zip(after.cold.iter()).enumerate() {
        assert_eq!(a.color_rgba8, b.color_rgba8, "cold record {i}");
        assert!((a.intensity - b.intensity).abs() <= 0.5 / 65535.0 + f32::EPSILON, "cold record {i}");
        let reach = (a.color_reach - b.color_reach).abs();
        assert!(reach <= a.color_reach * 2f32.powi(-11), "cold record {i}: {a:?} {b:?}");
    }
    errors
}

/// The largest error of a position along each axis of the block of `hot`: half a step, which
/// is under `2 extent / (2^21 - 2)`.
fn half_steps(hot: &[PatchHot]) -> [f64; 3] {
    std::array::from_fn(|axis| {
        let values = hot.iter().map(|h| f64::from(h.origin[axis]));
        let (low, high) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
        (high - low) / f64::from((1u32 << 21) - 2)
    })
}

fn round_trip(cloud_path: &Path, settings: &PrepSettings) -> (PatchSet, PatchSet, u64) {
    let cloud = read_point_cloud(cloud_path).unwrap_or_else(|e| panic!("{}: {e}", cloud_path.display()));
    let patches = prep(&cloud, settings, &NoProgress).expect("the cloud preps").0;
    let directory = tempfile::tempdir().unwrap();
    let store = directory.path().join("cloud.patches");
    patch_store::write(&store, &patches).unwrap();
    let bytes = std::fs::metadata(&store).unwrap().len();
    (patch_store::read(&store).unwrap(), patches, bytes)
}

/// The bytes of `loaded`'s coarse level in its store: 4 a block and 44 a coarse patch.
fn coarse_bytes(loaded: &PatchSet) -> u64 {
    let coarse = loaded.coarse.as_ref().expect("a compact store holds its coarse level");
    (4 * loaded.len().div_ceil(1024) + 44 * coarse.patches.len()) as u64
}

#[test]
fn the_bunny_round_trips_within_the_bounds_in_28_bytes_a_patch() {
    let (loaded, patches, bytes) = round_trip(&data_file("points/bunny.ply"), &PrepSettings::default());
    let errors = assert_within_compact_bounds(&patches, &loaded);
    let extent = patches.bounds().map(|b| (glam::Vec3::from(b.max) - glam::Vec3::from(b.min)).max_element());
    println!(
        "bunny: {errors:?}, extent {extent:?}, {:.2} bytes a patch",
        bytes as f64 / patches.len() as f64
    );
    assert!(patches.color_neighbors.is_empty());
    let records = bytes - coarse_bytes(&loaded);
    assert!(records as f64 / patches.len() as f64 <= 28.1, "{records} bytes for {} patches", patches.len());
    assert!(bytes as f64 / patches.len() as f64 <= 31.0, "{bytes} bytes with the coarse level");
    assert!(errors.position <= 1e-6 * f64::from(extent.unwrap()), "{errors:?}");
}

#[test]
fn a_real_sweep_keeps_its_positions_to_a_tenth_of_a_millimetre() {
    let sweep = data_file("scans/real/ouster_os1_32/scan00.bin");
    let (loaded, patches, bytes) = round_trip(&sweep, &PrepSettings::default());
    let errors = assert_within_compact_bounds(&patches, &loaded);
    let neighbour_bytes = 4 * patches.color_neighbors.len() as u64;
    let record_bytes = (bytes - neighbour_bytes - coarse_bytes(&loaded)) as f64 / patches.len() as f64;
    println!(
        "OS-1-32 sweep: {errors:?}, {record_bytes:.2} bytes a patch besides its colour neighbours and coarse level"
    );
    assert!(errors.position < 1e-4, "{} m", errors.position);
    assert!(record_bytes <= 34.1, "{record_bytes}");
}

#[test]
fn the_scan_structure_prep_found_is_recorded() {
    let directory = tempfile::tempdir().unwrap();
    let store = directory.path().join("scan.patches");
    let lines =
        ScanStructure::Lines { lines: 32, returns_on_lines: 990, patches: 1000, surface_patches: 700 };
    let reason =
        ScanStructure::Unstructured { reason: "more than 64 sensor positions, a moving sensor".into() };
    let patches =
        prep(&crate::common::sphere(300, 1.0, glam::DVec3::ZERO), &PrepSettings::default(), &NoProgress)
            .unwrap()
            .0;
    for scan in [ScanStructure::NotRecorded, ScanStructure::NotSought, lines, reason] {
        patch_store::write_with_scan(&store, &patches, &scan).unwrap();
        assert_eq!(patch_store::describe(&store).unwrap().scan, scan);
    }
}
