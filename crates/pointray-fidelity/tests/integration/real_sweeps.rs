//! Real sweeps (data/scans/real/, data/SOURCES.md) checked against their sensor's own rays:
//! prepped scan-aware, their patches must agree with the returns, in the dense check through
//! each return's pixel and ray by ray, and at least as well as unstructured patches do.
//!
//! Measured in release with the defaults: the KITTI sweep 000000 97.9% of pixels consistent
//! scan-aware against 72.4% unstructured, the Ouster OS-1-32 sweep 98.6% against 42.9%; rays
//! 98.8% and 99.3% consistent.

use std::sync::Arc;

use pointray_fidelity::{ConsistencyOptions, ConsistencyReport, sensor_ray_consistency};
use pointray_io::PointCloud;
use pointray_io::formats::read_point_cloud;
use pointray_patches::{PrepSettings, ScanMode};
use pointray_surface::{NoProgress, prep};
use pointray_test_support::data_file;

/// The dense check's share of consistent pixels, scan-aware.
const DENSE_BAR: f64 = 0.97;
/// The share of consistent rays, scan-aware.
const RAY_BAR: f64 = 0.97;

/// The sweep's patches, prepped with the defaults and `scan`, checked against its rays.
fn checked(cloud: &PointCloud, scan: ScanMode) -> ConsistencyReport {
    let settings = PrepSettings { scan, ..PrepSettings::default() };
    let (patches, prep_report) = prep(cloud, &settings, &NoProgress).expect("prep of the sweep");
    assert_eq!(prep_report.scan.is_some(), scan == ScanMode::Auto, "scan {scan:?}: {prep_report:?}");
    // The defaults check every return of these sweeps (up to 200,000).
    let options = ConsistencyOptions::default();
    let report = sensor_ray_consistency(cloud, Arc::new(patches), &options).expect("the sensor's rays");
    println!("scan {scan:?}:\n{report}");
    report
}

fn scan_aware_patches_agree_with_the_sensor(sweep: &str) {
    let cloud = read_point_cloud(&data_file(sweep)).expect("the sweep");
    assert!(cloud.rings.is_some(), "{sweep}: no scan lines recovered");
    let aware = checked(&cloud, ScanMode::Auto);
    let unstructured = checked(&cloud, ScanMode::Off);
    let dense = aware.pixels.consistent_fraction.expect("pixels checked");
    let dense_off = unstructured.pixels.consistent_fraction.expect("pixels checked");
    let rays = aware.consistent_fraction.expect("rays cast");
    println!("{sweep}: dense {dense:.4} scan-aware, {dense_off:.4} unstructured; rays {rays:.4}");
    assert!(dense >= DENSE_BAR, "{sweep}: {:.2}% of pixels consistent", 100.0 * dense);
    assert!(dense >= dense_off, "{sweep}: scan-aware {dense:.4} below unstructured {dense_off:.4}");
    assert!(rays >= RAY_BAR, "{sweep}: {:.2}% of rays consistent", 100.0 * rays);
}

#[test]
fn the_kitti_sweep_prepped_scan_aware_agrees_with_its_sensor() {
    scan_aware_patches_agree_with_the_sensor("scans/real/kitti_hdl64/000000.bin");
}

#[test]
fn the_os1_32_sweep_prepped_scan_aware_agrees_with_its_sensor() {
    scan_aware_patches_agree_with_the_sensor("scans/real/ouster_os1_32/scan00.bin");
}

/// A patch reaching further than this many footprints (its range times the angle between the
/// sensor's lines) is long and thin from anywhere but the sensor.
const SHARD_FOOTPRINTS: f32 = 8.0;

/// At most this share of the patches that are not level (ground, roofs) may be such shards.
/// Measured: 0.04% of the KITTI and OS-1-32 sweeps' patches, where an oblique plane is taken
/// on the returns' word alone 0.66% and 0.31%.
const SHARD_BAR: f64 = 0.001;

/// The share of the sweep's patches that are not level and reach past `SHARD_FOOTPRINTS` of
/// a sensor whose lines lie `line_spacing_degrees` apart, at the origin.
fn shard_share(sweep: &str, line_spacing_degrees: f32) -> f64 {
    let cloud = read_point_cloud(&data_file(sweep)).expect("the sweep");
    let (patches, _) = prep(&cloud, &PrepSettings::default(), &NoProgress).expect("prep of the sweep");
    let line_spacing = line_spacing_degrees.to_radians();
    let shards = patches
        .hot
        .iter()
        .filter(|patch| {
            let range = (patch.origin().as_dvec3() + patches.offset).length() as f32;
            let level = patch.normal().z.abs() >= 0.95;
            !level && patch.radius() > SHARD_FOOTPRINTS * range * line_spacing
        })
        .count();
    let share = shards as f64 / patches.len() as f64;
    println!("{sweep}: {shards} shards of {} patches", patches.len());
    share
}

#[test]
fn the_kitti_sweep_has_few_patches_long_and_thin_from_elsewhere() {
    // The HDL-64E spreads 64 lines over 26.9°.
    let share = shard_share("scans/real/kitti_hdl64/000000.bin", 26.9 / 63.0);
    assert!(share <= SHARD_BAR, "{:.3}% of patches are shards", 100.0 * share);
}

#[test]
fn the_os1_32_sweep_has_few_patches_long_and_thin_from_elsewhere() {
    // The OS-1-32 spreads 32 lines over 45°.
    let share = shard_share("scans/real/ouster_os1_32/scan00.bin", 45.0 / 31.0);
    assert!(share <= SHARD_BAR, "{:.3}% of patches are shards", 100.0 * share);
}
