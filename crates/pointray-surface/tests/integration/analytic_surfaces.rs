//! Patches of noise-free analytic surfaces.

use crate::common;

use glam::{DVec3, Vec3};
use pointray_patches::{PatchSet, PrepSettings};
use pointray_surface::{NoProgress, PrepReport, prep};

fn prep_default(cloud: &pointray_io::PointCloud) -> (PatchSet, PrepReport) {
    prep(cloud, &PrepSettings::default(), &NoProgress).expect("a clean analytic surface preps")
}

/// Every patch's surface over its disk lies on `z = height(x, y)` to within
/// `5e-4 d_i` (the coefficients are stored as half floats, good to about 2.4e-4 of each), and
/// every fit kept all six coefficients.
fn assert_reproduces_height_field(patches: &PatchSet, report: &PrepReport, height: impl Fn(f64, f64) -> f64) {
    assert_eq!(report.fits.quadratic, patches.len(), "fallbacks: {:?}", report.fits);
    for (i, patch) in patches.hot.iter().enumerate() {
        for p in common::surface_over_disk(patch, patches.offset) {
            let error = (p.z - height(p.x, p.y)).abs();
            assert!(
                error < 5e-4 * f64::from(patch.radius()),
                "patch {i}: error {error} at {p}, d_i {}",
                patch.radius()
            );
        }
    }
}

/// A quadric height field `w = f(u, v)` is exactly quadratic in a frame whose normal is
/// its axis; the input normals put the frames there, so the fit alone is under test.
fn with_axis_normals(mut cloud: pointray_io::PointCloud) -> pointray_io::PointCloud {
    cloud.normals = Some(vec![Vec3::Z; cloud.len()]);
    cloud
}

#[test]
fn paraboloid_is_reproduced_by_every_patch() {
    let height = |x: f64, y: f64| 0.3 * (x * x + y * y);
    let shift = DVec3::new(1000.0, -20.0, 3.0);
    let cloud = with_axis_normals(common::height_field(40, shift, height));
    let (patches, report) = prep_default(&cloud);
    assert_eq!(patches.len(), 1600);
    assert_reproduces_height_field(&patches, &report, |x, y| height(x - shift.x, y - shift.y) + shift.z);
}

#[test]
fn saddle_is_reproduced_by_every_patch() {
    let height = |x: f64, y: f64| 0.3 * (x * x - y * y);
    let cloud = with_axis_normals(common::height_field(40, DVec3::ZERO, height));
    let (patches, report) = prep_default(&cloud);
    assert_reproduces_height_field(&patches, &report, height);
}

#[test]
fn tilted_plane_is_reproduced_with_estimated_normals() {
    let height = |x: f64, y: f64| 0.4 * x - 0.7 * y + 0.2;
    let (patches, report) = prep_default(&common::height_field(40, DVec3::ZERO, height));
    assert_reproduces_height_field(&patches, &report, height);
    let up = DVec3::new(-0.4, 0.7, 1.0).normalize();
    let sides: Vec<f64> = patches.hot.iter().map(|p| p.normal().as_dvec3().dot(up)).collect();
    assert!(sides.iter().all(|&s| s.abs() > 1.0 - 1e-5), "normals off the plane's normal");
    assert!(sides.iter().all(|&s| s > 0.0) || sides.iter().all(|&s| s < 0.0), "normals on both sides");
}

#[test]
fn sphere_patches_stay_within_one_percent_and_one_degree() {
    let (radius, centre) = (2.0, DVec3::new(5.0, -3.0, 1.0));
    let (patches, _) = prep_default(&common::sphere(20_000, radius, centre));
    let mut outward = 0;
    for (i, patch) in patches.hot.iter().enumerate() {
        let d = f64::from(patch.radius());
        for p in common::surface_over_disk(patch, patches.offset) {
            let error = ((p - centre).length() - radius).abs();
            assert!(error < 0.01 * d, "patch {i}: height error {error} is over 1% of d_i {d}");
        }
        let radial = (patch.origin().as_dvec3() + patches.offset - centre).normalize();
        let normal = patch.normal().as_dvec3();
        let degrees = normal.dot(radial).abs().min(1.0).acos().to_degrees();
        assert!(degrees < 1.0, "patch {i}: normal {degrees}° off");
        let [_, c1, c2, ..] = patch.decode().coefficients;
        let surface_normal =
            patch.decode().direction_to_world(Vec3::new(-c1, -c2, 1.0).normalize()).as_dvec3();
        let surface_degrees = surface_normal.dot(radial).abs().min(1.0).acos().to_degrees();
        assert!(surface_degrees < 1.0, "patch {i}: surface normal {surface_degrees}° off");
        outward += usize::from(normal.dot(radial) > 0.0);
    }
    assert!(outward == 0 || outward == patches.len(), "{outward} of {} normals point outward", patches.len());
}

#[test]
fn fits_fall_back_on_a_line_of_scanlines() {
    // Points on two parallel lines: every neighbourhood is (nearly) one-dimensional in
    // v², so quadratics must fall back rather than explode.
    let positions: Vec<DVec3> =
        (0..200).map(|i| DVec3::new((i / 2) as f64 * 0.01, (i % 2) as f64 * 0.5, 0.0)).collect();
    let (patches, report) = prep_default(&pointray_io::PointCloud::from_positions(positions));
    assert!(report.fits.quadratic < patches.len(), "{:?}", report.fits);
    for patch in &patches.hot {
        assert!(patch.decode().coefficients.iter().all(|c| c.is_finite()));
        // The points lie in z = 0: the fit's offset, folded into the origin, stays within reach.
        assert!(patch.origin().z.abs() <= patch.radius(), "{patch:?}");
    }
    assert_eq!(report.fits.quadratic + report.fits.plane + report.fits.flat, patches.len());
}
