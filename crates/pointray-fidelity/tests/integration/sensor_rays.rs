//! Sensor-ray consistency on synthetic scans whose answers are known: clean ground, ground
//! with a floating blob in front of it, ground whose surface has a hole under some returns.

use std::sync::Arc;

use glam::DVec3;
use pointray_fidelity::{
    ConsistencyOptions, ConsistencyReport, ReturnOrigins, sensor_ray_consistency,
    support_against_beam_spacing,
};
use pointray_io::PointCloud;
use pointray_patches::{PatchSet, PrepSettings};
use pointray_surface::{NoProgress, PrepReport, prep};

use crate::ring_scan::{SENSOR, ground_scan, without};

fn patches_of(cloud: &PointCloud) -> (PatchSet, PrepReport) {
    prep(cloud, &PrepSettings::default(), &NoProgress).expect("prep of the synthetic scan")
}

fn check(cloud: &PointCloud, patches: PatchSet) -> ConsistencyReport {
    let report = sensor_ray_consistency(cloud, Arc::new(patches), &ConsistencyOptions::default()).unwrap();
    println!("{report}");
    report
}

#[test]
fn clean_ground_seen_from_its_sensor_is_consistent() {
    let cloud = ground_scan();
    let report = check(&cloud, patches_of(&cloud).0);
    assert_eq!(report.counts.rays, cloud.len());
    assert!(report.consistent_fraction.unwrap() >= 0.99, "{report:?}");
    assert!(report.occluded_in_front_fraction.unwrap() <= 0.005, "{report:?}");
}

/// A ball of radius 0.3 floating 1 above the ground, 3 in front of the sensor.
const BLOB_CENTRE: DVec3 = DVec3::new(3.0, 0.0, 1.0);
const BLOB_RADIUS: f64 = 0.3;

fn blob_points(count: usize) -> Vec<DVec3> {
    let golden_angle = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..count)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / count as f64;
            let ring = (1.0 - z * z).sqrt();
            let angle = golden_angle * i as f64;
            BLOB_CENTRE + DVec3::new(ring * angle.cos(), ring * angle.sin(), z) * BLOB_RADIUS
        })
        .collect()
}

/// Whether the ray from the sensor to `point` passes within `radius` of the blob's centre
/// before reaching it.
fn passes_the_blob(point: DVec3, radius: f64) -> bool {
    let direction = (point - SENSOR).normalize();
    let along = (BLOB_CENTRE - SENSOR).dot(direction);
    let closest = SENSOR + direction * along;
    along > 0.0 && along < (point - SENSOR).length() && closest.distance(BLOB_CENTRE) < radius
}

#[test]
fn a_blob_floating_in_front_of_the_ground_is_reported_as_floaters() {
    let ground = ground_scan();
    let hidden = ground.positions.iter().filter(|&&p| passes_the_blob(p, 0.8 * BLOB_RADIUS)).count();
    let shadowed = ground.positions.iter().filter(|&&p| passes_the_blob(p, 1.2 * BLOB_RADIUS)).count();
    assert!(hidden >= 20, "the blob should hide a few dozen returns, hides {hidden}");
    let blob = blob_points(400);
    let mut cloud =
        PointCloud::from_positions(ground.positions.iter().copied().chain(blob.iter().copied()).collect());
    cloud.sensor_position = Some(SENSOR);
    let report = check(&cloud, patches_of(&cloud).0);
    // Each hidden return is a floater, and so is the blob's far side, seen through its near
    // side; nothing else should be.
    let floaters = report.counts.occluded_in_front;
    assert!(floaters >= hidden, "{floaters} floaters, {hidden} returns hidden behind the blob");
    assert!(floaters <= shadowed + blob.len() * 3 / 4, "{floaters} floaters: more than the blob explains");
}

#[test]
fn returns_over_a_hole_in_the_surface_pass_through() {
    let cloud = ground_scan();
    let in_disc = |p: DVec3, radius: f64| (p - DVec3::new(5.0, 2.0, 0.0)).length() < radius;
    // Patches at the rim reach into the hole by up to their k-th neighbour's distance (about
    // 0.45 here), so returns more than half way in are surely over the hole.
    let inner = cloud.positions.iter().filter(|&&p| in_disc(p, 0.5)).count();
    let outer = cloud.positions.iter().filter(|&&p| in_disc(p, 1.3)).count();
    assert!(inner >= 10, "the hole should take some returns, takes {inner}");
    let holed = patches_of(&without(&cloud, |p| in_disc(p, 1.0))).0;
    let report = check(&cloud, holed);
    let holes = report.counts.passed_through;
    assert!(holes >= inner && holes <= outer, "{holes} passed through; {inner} to {outer} expected");
    // Below the ground there is nothing: the rays through the hole meet no surface at all.
    assert!(report.counts.missed >= inner, "{report:?}");
}

#[test]
fn a_large_cloud_is_subsampled_to_the_ray_budget() {
    let cloud = ground_scan();
    let options = ConsistencyOptions { rays: 500, ..ConsistencyOptions::default() };
    let report = sensor_ray_consistency(&cloud, Arc::new(patches_of(&cloud).0), &options).unwrap();
    assert_eq!((report.counts.rays, report.returns), (500, cloud.len()));
}

#[test]
fn a_scan_with_no_sensor_is_an_error_that_says_how_to_give_one() {
    let mut cloud = ground_scan();
    cloud.sensor_position = None;
    let patches = Arc::new(patches_of(&cloud).0);
    let error = sensor_ray_consistency(&cloud, patches, &ConsistencyOptions::default()).unwrap_err();
    assert!(error.to_string().contains("--sensor"), "{error}");
}

#[test]
fn support_ratios_are_radii_over_the_one_degree_ring_gap_on_the_ground() {
    let cloud = ground_scan();
    let (patches, prep_report) = patches_of(&cloud);
    let origins = ReturnOrigins::of_cloud(&cloud, None).unwrap();
    let sources = &prep_report.patch_sources;
    let support = support_against_beam_spacing(&cloud, &patches, sources, &origins, glam::Vec3::Z).unwrap();
    println!("{support:?}");
    assert_eq!((support.patches, support.rings), (patches.len(), 29));
    // Every ring lies 1° from the next, so each patch's beam spacing on the ground is its range
    // times 1° over the cosine of the beam's incidence on the patch.
    let expected_max = patches
        .hot
        .iter()
        .map(|patch| {
            let to_patch = patch.origin().as_dvec3() + patches.offset - SENSOR;
            let range = to_patch.length();
            let cosine = (to_patch.dot(patch.normal().as_dvec3()) / range).abs().max(0.05);
            f64::from(patch.radius()) / (range * 1f64.to_radians() / cosine)
        })
        .fold(0.0, f64::max);
    assert!(
        (support.max_ratio - expected_max).abs() < 1e-3 * expected_max,
        "{support:?} against {expected_max}"
    );
    assert!(support.p99_ratio > 0.0 && support.p99_ratio <= support.max_ratio, "{support:?}");
}
