//! `PrepSettings::disk_scale` shrinks how far each patch reaches, and nothing else: the same
//! fits over the same neighbourhoods, radii scaled, boxes around the smaller disks.

use crate::common;

use glam::DVec3;
use pointray_patches::{PatchSet, PrepSettings};
use pointray_surface::{NoProgress, PrepError, prep};

fn prepped(cloud: &pointray_io::PointCloud, disk_scale: f32) -> Result<PatchSet, PrepError> {
    let options = PrepSettings { disk_scale, ..PrepSettings::default() };
    prep(cloud, &options, &NoProgress).map(|(patches, _)| patches)
}

#[test]
fn a_smaller_disk_scales_the_radii_and_keeps_the_fits() {
    let cloud = common::height_field(30, DVec3::ZERO, |x, y| 0.2 * x * x - 0.1 * x * y + 0.3 * y);
    let paper = prepped(&cloud, 1.0).expect("preps");
    let smaller = prepped(&cloud, 0.7).expect("preps");
    assert_eq!(smaller.settings.disk_scale, 0.7);
    for (i, (a, b)) in paper.hot.iter().zip(&smaller.hot).enumerate() {
        // The coefficients are stored as half floats scaled by the radius, so they agree to a
        // half float's precision.
        for (x, y) in a.decode().coefficients.iter().zip(b.decode().coefficients) {
            assert!((x - y).abs() <= 1e-3 * x.abs().max(1e-3), "patch {i}: the fit changed: {x} vs {y}");
        }
        assert_eq!(a.origin(), b.origin(), "patch {i}");
        assert!((b.radius() - 0.7 * a.radius()).abs() <= 1e-6 * a.radius(), "patch {i}: radius not scaled");
    }
    for (i, (a, b)) in paper.aabbs.iter().zip(&smaller.aabbs).enumerate() {
        let (size_a, size_b) = (a.max[0] - a.min[0], b.max[0] - b.min[0]);
        assert!(size_b < size_a, "patch {i}: the box did not shrink ({size_b} >= {size_a})");
    }
}

#[test]
fn disk_scales_outside_the_range_are_refused() {
    let cloud = common::height_field(10, DVec3::ZERO, |_, _| 0.0);
    for bad in [0.0, -0.5, 2.5, f32::NAN] {
        let error = prepped(&cloud, bad).expect_err("a bad disk scale must be refused");
        assert!(error.to_string().contains("disk_scale"), "{error}");
    }
}
