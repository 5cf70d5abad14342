//! Scan-aware patches on a simulated spinning-LiDAR sweep of a street-like scene: a ground
//! plane and a wall, seen from a sensor 1.8 m up.

use glam::{DVec3, Vec2};
use pointray_io::PointCloud;
use pointray_surface::{NoProgress, PatchSet, PrepSettings, ScanMode, prep};

const SENSOR: DVec3 = DVec3::new(0.0, 0.0, 1.8);
const WALL_X: f64 = 12.0;

/// A 32-beam sweep (elevations -25° to +5°, 0.2° azimuth steps) of the ground `z = 0` and a
/// wall `x = 12`, with range noise of `noise` metres (deterministic).
fn sweep(noise: f64) -> (PointCloud, Vec<u16>) {
    let mut positions = Vec::new();
    let mut rings = Vec::new();
    for beam in 0..32u16 {
        let elevation = (-25.0 + f64::from(beam) * 30.0 / 31.0).to_radians();
        for step in 0..1800 {
            let azimuth = (step as f64 * 0.2).to_radians();
            let direction =
                DVec3::new(azimuth.cos() * elevation.cos(), azimuth.sin() * elevation.cos(), elevation.sin());
            let ground = if direction.z < 0.0 { -SENSOR.z / direction.z } else { f64::INFINITY };
            let wall = if direction.x > 0.0 { WALL_X / direction.x } else { f64::INFINITY };
            let range = ground.min(wall);
            if range > 40.0 {
                continue;
            }
            let jitter = noise * (((step * 31 + usize::from(beam) * 17) % 101) as f64 / 50.0 - 1.0);
            positions.push(SENSOR + direction * (range + jitter));
            rings.push(beam);
        }
    }
    let cloud = PointCloud { positions, sensor_position: Some(SENSOR), ..PointCloud::default() };
    (cloud, rings)
}

fn prepped(cloud: &PointCloud, scan: ScanMode) -> PatchSet {
    prep(cloud, &PrepSettings { scan, ..PrepSettings::default() }, &NoProgress).expect("prep").0
}

/// The fraction of `probes` (input coordinates on the ground) that some patch's support
/// covers, judged in each patch's tangent plane.
fn covered_fraction(patches: &PatchSet, probes: &[DVec3]) -> f64 {
    let decoded: Vec<_> = patches.hot.iter().map(|h| h.decode()).collect();
    let covered = probes
        .iter()
        .filter(|&&probe| {
            let local = (probe - patches.offset).as_vec3();
            decoded.iter().any(|patch| {
                let offset = patch.to_local(local);
                (offset.x.abs() <= patch.radii.x)
                    && patch.supports(Vec2::new(offset.x, offset.y))
                    && offset.z.abs() < 0.1
            })
        })
        .count();
    covered as f64 / probes.len() as f64
}

/// Ground probes between 4 and 15 m from the sensor, away from the wall.
fn ground_probes() -> Vec<DVec3> {
    (0..400)
        .map(|i| {
            let (range, angle) =
                (4.0 + 11.0 * ((i * 37) % 400) as f64 / 400.0, (i as f64 * 0.9).to_radians() + 1.7);
            DVec3::new(range * angle.cos(), range * angle.sin(), 0.0)
        })
        .filter(|probe| probe.x < WALL_X - 0.5)
        .collect()
}

#[test]
fn ring_gaps_on_the_ground_are_bridged_only_with_the_scan_structure() {
    let (mut cloud, rings) = sweep(0.0);
    cloud.rings = Some(rings);
    let probes = ground_probes();
    let unstructured = covered_fraction(&prepped(&cloud, ScanMode::Off), &probes);
    let scan_aware = covered_fraction(&prepped(&cloud, ScanMode::Auto), &probes);
    assert!(unstructured < 0.8, "the unstructured patches already cover {unstructured} of the ground");
    assert!(scan_aware > 0.99, "scan-aware patches cover only {scan_aware} of the ground");
}

#[test]
fn beams_recovered_from_elevations_bridge_the_gaps_too_under_noise() {
    let (cloud, _) = sweep(0.01);
    let covered = covered_fraction(&prepped(&cloud, ScanMode::Auto), &ground_probes());
    assert!(covered > 0.98, "covered {covered}");
}

#[test]
fn ground_normals_point_up_and_no_support_exceeds_three_line_spacings() {
    let (mut cloud, rings) = sweep(0.005);
    cloud.rings = Some(rings);
    let patches = prepped(&cloud, ScanMode::Auto);
    let beam_step = (30.0f32 / 31.0).to_radians();
    let mut ground = 0;
    for hot in &patches.hot {
        let patch = hot.decode();
        let world = patch.origin.as_dvec3() + patches.offset;
        if world.z.abs() > 0.05 || world.x > WALL_X - 1.0 {
            continue;
        }
        ground += 1;
        assert!(patch.frame.n.z > 0.97, "ground patch at {world} has normal {}", patch.frame.n);
        // The spacing between rings on the ground at this range and grazing angle.
        let range = (world - SENSOR).length() as f32;
        let grazing = (SENSOR.z as f32 / range).asin();
        let ring_gap = range * beam_step / grazing.sin();
        assert!(
            patch.radii.x <= 3.0 * ring_gap.max(range * 0.2f32.to_radians()),
            "{world}: {:?} vs gap {ring_gap}",
            patch.radii
        );
    }
    assert!(ground > 10_000);
}

#[test]
fn the_wall_and_the_ground_are_not_bridged() {
    let (mut cloud, rings) = sweep(0.0);
    cloud.rings = Some(rings);
    let patches = prepped(&cloud, ScanMode::Auto);
    // Probes in the air in front of the wall, above the ground: nothing should cover them.
    let air: Vec<DVec3> = (0..100).map(|i| DVec3::new(WALL_X - 0.5, -3.0 + 0.06 * i as f64, 0.6)).collect();
    let decoded: Vec<_> = patches.hot.iter().map(|h| h.decode()).collect();
    for probe in air {
        let local = (probe - patches.offset).as_vec3();
        let hit = decoded.iter().find(|patch| {
            let offset = patch.to_local(local);
            patch.supports(Vec2::new(offset.x, offset.y)) && offset.z.abs() < 0.05
        });
        assert!(
            hit.is_none(),
            "{probe} lies on a patch at {}",
            hit.unwrap().origin.as_dvec3() + patches.offset
        );
    }
}
