//! Cameras placed by the user: explicit positions and targets, `above` and the sensor's
//! views, each checked by how much of the mesh it sees.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use pointray_fidelity::{
    CpuImageRenderer, FidelityOptions, FidelityReport, SensorPose, ViewSpec, measure_fidelity,
};
use pointray_io::{PointCloud, TriangleMesh};
use pointray_patches::PrepSettings;
use pointray_scene::PatchAcceptance;
use pointray_surface::{NoProgress, prep};

use crate::ring_scan::{HIGHEST_BEAM, LOWEST_BEAM, SENSOR, ground_scan};

const SIZE: u32 = 64;

/// A square of side `2 * half` on z = 0 around `centre`, as two triangles.
fn square(centre: Vec3, half: f32) -> TriangleMesh {
    let corner = |x: f32, y: f32| centre + Vec3::new(x * half, y * half, 0.0);
    TriangleMesh {
        positions: vec![corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// A grid of points over that square.
fn square_points(centre: Vec3, half: f32, per_side: usize) -> PointCloud {
    let step = 2.0 * half / (per_side - 1) as f32;
    let positions = (0..per_side * per_side)
        .map(|i| {
            let offset = Vec3::new((i % per_side) as f32, (i / per_side) as f32, 0.0) * step - half;
            (centre + Vec3::new(offset.x, offset.y, 0.0)).as_dvec3()
        })
        .collect();
    PointCloud::from_positions(positions)
}

fn measure(points: &PointCloud, mesh: TriangleMesh, options: &FidelityOptions) -> FidelityReport {
    let (patches, _) = prep(points, &PrepSettings::default(), &NoProgress).unwrap();
    let report = measure_fidelity(Arc::new(patches), Arc::new(mesh), options, &CpuImageRenderer).unwrap();
    println!("{report}");
    report
}

/// The square of side 2 at (5, 0, 0), seen from 10 above with a 20° lens, fills
/// `(2 / (2 * 10 * tan 10°))²` of the image.
fn covered_fraction() -> f64 {
    (2.0 / (20.0 * 10f64.to_radians().tan())).powi(2)
}

fn assert_fills(report: &FidelityReport, view: usize, fraction: f64) {
    let pixels = report.views[view].metrics.mesh_pixels as f64;
    let expected = fraction * f64::from(SIZE * SIZE);
    assert!(
        (pixels - expected).abs() < 0.05 * expected,
        "view {view}: {pixels} mesh pixels, {expected} expected"
    );
}

#[test]
fn explicit_views_see_what_they_are_aimed_at_and_nothing_else() {
    let centre = Vec3::new(5.0, 0.0, 0.0);
    let views = vec![
        ViewSpec::Explicit { from: Vec3::new(5.0, 0.0, 10.0), at: centre },
        ViewSpec::Explicit { from: Vec3::new(-5.0, 0.0, 10.0), at: Vec3::new(-5.0, 0.0, 0.0) },
        ViewSpec::Above { height: 10.0 },
    ];
    let mut options = FidelityOptions::with_views(views, SIZE, PatchAcceptance::Disk);
    options.fov_degrees = 20.0;
    let report = measure(&square_points(centre, 1.0, 21), square(centre, 1.0), &options);
    assert_eq!(report.views.len(), 3);
    assert_fills(&report, 0, covered_fraction());
    assert_eq!(report.views[1].metrics.mesh_pixels, 0, "the square lies far outside the second view");
    // `above` looks down on the points' centre, the square's: the first view again.
    assert_eq!(report.views[2].position, [5.0, 0.0, 10.0]);
    assert_fills(&report, 2, covered_fraction());
    assert!(report.views[0].metrics.hole_rate.unwrap() < 0.01, "{:?}", report.views[0].metrics);
}

#[test]
fn sensor_views_ring_the_horizon_over_the_band_the_beams_swept() {
    let cloud = ground_scan();
    let mesh = square(Vec3::ZERO, 20.0);
    let mut options =
        FidelityOptions::with_views(vec![ViewSpec::Sensor { yaws: 4 }], SIZE, PatchAcceptance::Disk);
    let sensor = SensorPose::of_cloud(&cloud, Vec3::Z, None).unwrap();
    let [low, high] = sensor.elevation_degrees;
    assert!(
        (low - LOWEST_BEAM as f32).abs() < 1e-3 && (high - HIGHEST_BEAM as f32).abs() < 1e-3,
        "{low} {high}"
    );
    options.sensor = Some(sensor);
    let report = measure(&cloud, mesh, &options);
    assert_eq!(report.views.len(), 4);
    // 90° wide, 28° tall: 64 pixels by 64 tan 14°.
    let height = (f64::from(SIZE) * 14f64.to_radians().tan()).round() as u32;
    for (view, yaw) in report.views.iter().zip([0.0f32, 90.0, 180.0, 270.0]) {
        assert_eq!((view.width, view.height), (SIZE, height), "{}", view.label);
        assert_eq!(view.position, SENSOR.as_vec3().to_array());
        let forward = Vec3::from(view.look_at) - Vec3::from(view.position);
        let expected = crate::ring_scan::beam(-26.0, f64::from(yaw)).as_vec3();
        assert!(forward.normalize().distance(expected) < 1e-4, "{}: {forward:?}", view.label);
    }
    // Every pixel sees ground: the band holds no sky and no ground nearer than the lowest beam.
    assert_eq!(report.overall.mesh_pixels, u64::from(4 * SIZE * height));
}

#[test]
fn sensor_views_without_a_sensor_are_an_error() {
    let cloud = square_points(Vec3::ZERO, 1.0, 11);
    let options =
        FidelityOptions::with_views(vec![ViewSpec::Sensor { yaws: 4 }], SIZE, PatchAcceptance::Disk);
    let (patches, _) = prep(&cloud, &PrepSettings::default(), &NoProgress).unwrap();
    let result =
        measure_fidelity(Arc::new(patches), Arc::new(square(Vec3::ZERO, 1.0)), &options, &CpuImageRenderer);
    assert!(result.unwrap_err().to_string().contains("no sensor position"));
    let no_position = SensorPose::of_cloud(&cloud, Vec3::Z, None).unwrap_err();
    assert!(no_position.to_string().contains("--sensor"), "{no_position}");
    let flat = SensorPose::of_cloud(&cloud, Vec3::Z, Some(DVec3::ZERO)).unwrap_err();
    assert!(flat.to_string().contains("no band"), "{flat}");
}

#[test]
fn bad_lenses_up_axes_and_sizes_are_errors() {
    let cloud = square_points(Vec3::ZERO, 1.0, 11);
    let (patches, _) = prep(&cloud, &PrepSettings::default(), &NoProgress).unwrap();
    let (patches, mesh) = (Arc::new(patches), Arc::new(square(Vec3::ZERO, 1.0)));
    let base =
        FidelityOptions::with_views(vec![ViewSpec::Above { height: 5.0 }], SIZE, PatchAcceptance::Disk);
    let broken = [
        FidelityOptions { fov_degrees: 0.0, ..base.clone() },
        FidelityOptions { fov_degrees: 180.0, ..base.clone() },
        FidelityOptions { up: Vec3::ZERO, ..base.clone() },
        FidelityOptions { up: Vec3::new(f32::NAN, 0.0, 1.0), ..base.clone() },
        FidelityOptions { size: 0, ..base.clone() },
        FidelityOptions { size: 100_000, ..base.clone() },
        FidelityOptions { views: vec![], ..base.clone() },
        FidelityOptions { views: vec![ViewSpec::Above { height: -1.0 }], ..base.clone() },
    ];
    for options in broken {
        let result = measure_fidelity(patches.clone(), mesh.clone(), &options, &CpuImageRenderer);
        assert!(result.is_err(), "{options:?} should be refused");
    }
    assert!(measure_fidelity(patches, mesh, &base, &CpuImageRenderer).is_ok());
}
