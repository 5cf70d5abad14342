//! Spinning-LiDAR sweeps of the procedural street, prepped scan-aware with the defaults, held
//! to the LiDAR bars against the street's mesh and against the sensor's own rays.
//! Sensors, noise, dropout and seeds vary, so that no bar holds for one simulated scan alone.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use pointray_fidelity::{
    ConsistencyOptions, CpuImageRenderer, FidelityMetrics, FidelityOptions, ReturnOrigins, SensorPose,
    ViewSpec, measure_fidelity, sensor_ray_consistency, support_against_beam_spacing,
};
use pointray_io::{PointCloud, TriangleMesh};
use pointray_lidar::street::street;
use pointray_lidar::{
    LidarScene, NoProgress, Sensor, SensorPreset, UpAxis, merged_mesh, scan, to_point_cloud,
};
use pointray_patches::{PatchSet, PrepSettings};
use pointray_scene::PatchAcceptance;
use pointray_surface::NoProgress as NoPrepProgress;
use pointray_surface::{PrepReport, prep};

/// Sensor views this many pixels wide; the view from above is this square.
const SIZE: u32 = 256;
/// The view from above stands this high over the sensor.
const ABOVE_METRES: f32 = 20.0;

struct Sweep {
    preset: SensorPreset,
    range_noise: f64,
    dropout: f64,
    seed: u64,
}

/// The preset's published noise, and a noisier, lossier sensor.
const SWEEPS: [Sweep; 4] = [
    Sweep { preset: SensorPreset::Hdl64, range_noise: 0.02, dropout: 0.0, seed: 1 },
    Sweep { preset: SensorPreset::Hdl64, range_noise: 0.03, dropout: 0.1, seed: 2 },
    Sweep { preset: SensorPreset::Hdl32, range_noise: 0.02, dropout: 0.0, seed: 3 },
    Sweep { preset: SensorPreset::Hdl32, range_noise: 0.03, dropout: 0.1, seed: 4 },
];

struct Scanned {
    cloud: PointCloud,
    mesh: Arc<TriangleMesh>,
    patches: Arc<PatchSet>,
    report: PrepReport,
}

fn scanned(sweep: &Sweep) -> Scanned {
    let surfaces = street(None).expect("the street");
    let scene = LidarScene::from_surfaces(&surfaces, UpAxis::Z).expect("a scene");
    let sensor = Sensor { range_noise: sweep.range_noise, dropout: sweep.dropout, ..sweep.preset.sensor() };
    let station =
        pointray_lidar::SensorPose { position: DVec3::new(0.0, 0.0, sensor.mount_height), yaw_deg: 0.0 };
    let returns = scan(&scene, &sensor, &[station], sweep.seed, &NoProgress).expect("a sweep").returns;
    let cloud = to_point_cloud(&returns);
    let (patches, report) = prep(&cloud, &PrepSettings::default(), &NoPrepProgress).expect("prep");
    assert!(report.scan.is_some(), "{}: the scan structure was not used", sweep.preset.key());
    Scanned { cloud, mesh: Arc::new(merged_mesh(&surfaces)), patches: Arc::new(patches), report }
}

fn fidelity(scanned: &Scanned, view: ViewSpec, name: &str) -> FidelityMetrics {
    let mut options = FidelityOptions::with_views(vec![view], SIZE, PatchAcceptance::Disk);
    if let Some(folder) = std::env::var_os("STREET_IMAGES") {
        let folder = std::path::PathBuf::from(folder)
            .join(format!("{name}-{view:?}").replace([' ', '{', '}', ':'], ""));
        std::fs::create_dir_all(&folder).unwrap();
        options.image_folder = Some(folder);
    }
    options.sensor = Some(SensorPose::of_cloud(&scanned.cloud, Vec3::Z, None).expect("a sensor"));
    let report = measure_fidelity(scanned.patches.clone(), scanned.mesh.clone(), &options, &CpuImageRenderer)
        .expect("fidelity");
    report.overall
}

/// The LiDAR bars, which these sweeps meet: holes from the sensor ≤ 0.5 % (0.22–0.42 %
/// measured), from above ≤ 2 % (0.5–1.1 %), false surface ≤ 1 % (0.05–0.13 %), mean normal
/// error ≤ 5° from the sensor (3.6–4.7°) and from above (1.7–2.6°), ≥ 98 % consistent.
struct Bars {
    sensor_seen_holes: f64,
    above_seen_holes: f64,
    false_surface: f64,
    sensor_normal_degrees: f64,
    above_normal_degrees: f64,
    consistent: f64,
}

const BARS: Bars = Bars {
    sensor_seen_holes: 0.005,
    above_seen_holes: 0.02,
    false_surface: 0.01,
    sensor_normal_degrees: 5.0,
    above_normal_degrees: 5.0,
    consistent: 0.98,
};

#[test]
fn street_sweeps_hold_their_fidelity_and_consistency() {
    for sweep in &SWEEPS {
        let name = format!("{} noise {} dropout {}", sweep.preset.key(), sweep.range_noise, sweep.dropout);
        let scanned = scanned(sweep);
        let from_sensor = fidelity(&scanned, ViewSpec::Sensor { yaws: 4 }, &name);
        let from_above = fidelity(&scanned, ViewSpec::Above { height: ABOVE_METRES }, &name);
        let consistency =
            sensor_ray_consistency(&scanned.cloud, scanned.patches.clone(), &ConsistencyOptions::default())
                .expect("consistency");
        let origins = ReturnOrigins::of_cloud(&scanned.cloud, None).expect("origins");
        let sources = &scanned.report.patch_sources;
        let support =
            support_against_beam_spacing(&scanned.cloud, &scanned.patches, sources, &origins, Vec3::Z)
                .expect("support");
        let summary = format!(
            "{name}: sensor {from_sensor:?}\nabove {from_above:?}\n{:?}\n{support:?}",
            consistency.counts
        );
        println!("{summary}");
        let seen_holes = |m: &FidelityMetrics| m.seen_hole_rate.expect("a sensor");
        let normal = |m: &FidelityMetrics| m.normal_error_mean_degrees.expect("pixels both hit");
        assert!(seen_holes(&from_sensor) <= BARS.sensor_seen_holes, "{summary}");
        assert!(seen_holes(&from_above) <= BARS.above_seen_holes, "{summary}");
        for metrics in [&from_sensor, &from_above] {
            assert!(metrics.false_surface_rate.expect("mesh pixels") <= BARS.false_surface, "{summary}");
        }
        assert!(normal(&from_sensor) <= BARS.sensor_normal_degrees, "{summary}");
        assert!(normal(&from_above) <= BARS.above_normal_degrees, "{summary}");
        assert!(consistency.consistent_fraction.expect("rays") >= BARS.consistent, "{summary}");
        assert_eq!(support.over_limit_fraction, 0.0, "a patch reaches past 3 beam spacings: {summary}");
    }
}

/// A 16-beam sweep, whose cars three or four lines cross: holes from the sensor and false
/// surface within the bars. The holes were 1.1–1.3 % while a level plane through a return on a
/// car's side, taking in the road metres beyond, outvoted the car's next line.
#[test]
fn a_sixteen_beam_sweep_leaves_the_cars_whole() {
    let sweep = Sweep { preset: SensorPreset::Vlp16, range_noise: 0.03, dropout: 0.0, seed: 5 };
    let from_sensor = fidelity(&scanned(&sweep), ViewSpec::Sensor { yaws: 4 }, "vlp16");
    let holes = from_sensor.seen_hole_rate.expect("a sensor");
    assert!(holes <= 0.005, "holes from the sensor {holes}: {from_sensor:?}");
    let false_surface = from_sensor.false_surface_rate.expect("mesh pixels");
    assert!(false_surface <= BARS.false_surface, "false surface {false_surface}: {from_sensor:?}");
}

/// A 128-beam sweep, whose lines on the road beside the car lie 3–6 cm apart, about its 3 cm of
/// range noise, so that the noise moves returns past the next line's: holes within the bars
/// from the sensor and from above. They were 1.0 % and 2.7 % while such a return, moved beside
/// the point, was taken for the next line and held the patch to a sliver. Its mean normal
/// error is within the bar from both views too: from the sensor it was 5.7° while each
/// return's plane, fitted to returns a few centimetres apart, took the noise's tilt unsmoothed.
#[test]
fn a_sweep_whose_lines_interleave_in_the_noise_leaves_no_holes_between_them() {
    let sweep = Sweep { preset: SensorPreset::Os128, range_noise: 0.03, dropout: 0.0, seed: 1 };
    let scanned = scanned(&sweep);
    let from_sensor = fidelity(&scanned, ViewSpec::Sensor { yaws: 4 }, "os128");
    let from_above = fidelity(&scanned, ViewSpec::Above { height: ABOVE_METRES }, "os128");
    let holes = |m: &FidelityMetrics| m.seen_hole_rate.expect("a sensor");
    assert!(holes(&from_sensor) <= 0.005, "holes from the sensor: {from_sensor:?}");
    assert!(holes(&from_above) <= BARS.above_seen_holes, "holes from above: {from_above:?}");
    let normal = |m: &FidelityMetrics| m.normal_error_mean_degrees.expect("pixels both hit");
    assert!(normal(&from_sensor) <= BARS.sensor_normal_degrees, "normals from the sensor: {from_sensor:?}");
    assert!(normal(&from_above) <= BARS.above_normal_degrees, "normals from above: {from_above:?}");
}
