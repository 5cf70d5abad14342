//! Scan-aware patches on simulated spinning-LiDAR sweeps of street-like scenes, seen from a
//! sensor 1.8 m up: a ground plane and a wall, and a road, a kerb and a sidewalk.

use glam::{DVec3, Vec2};
use pointray_io::PointCloud;
use pointray_kernels::Patch;
use pointray_patches::{PatchSet, PrepSettings, ScanMode};
use pointray_surface::{NoProgress, prep};

const SENSOR: DVec3 = DVec3::new(0.0, 0.0, 1.8);
const WALL_X: f64 = 12.0;

/// A 32-beam sweep (elevations -25° to +5°, 0.2° azimuth steps) of the ground `z = 0` and a
/// wall `x = 12`, out to 40 m, with range noise of `noise` metres (deterministic).
fn sweep(noise: f64) -> (PointCloud, Vec<u16>) {
    let (positions, rings) = sweep_scene(noise, |direction| {
        let ground = if direction.z < 0.0 { -SENSOR.z / direction.z } else { f64::INFINITY };
        let wall = if direction.x > 0.0 { WALL_X / direction.x } else { f64::INFINITY };
        Some(ground.min(wall)).filter(|&range| range <= 40.0)
    });
    let cloud = PointCloud { positions, sensor_position: Some(SENSOR), ..PointCloud::default() };
    (cloud, rings)
}

/// The returns and their beams of a 32-beam sweep (as `sweep`) of the scene whose first hit
/// along a direction from the sensor lies at `range` (none when the ray is not kept).
fn sweep_scene(noise: f64, range: impl Fn(DVec3) -> Option<f64>) -> (Vec<DVec3>, Vec<u16>) {
    let mut positions = Vec::new();
    let mut rings = Vec::new();
    for beam in 0..32u16 {
        let elevation = (-25.0 + f64::from(beam) * 30.0 / 31.0).to_radians();
        for step in 0..1800 {
            let azimuth = (step as f64 * 0.2).to_radians();
            let direction =
                DVec3::new(azimuth.cos() * elevation.cos(), azimuth.sin() * elevation.cos(), elevation.sin());
            let Some(range) = range(direction) else { continue };
            let jitter = noise * (((step * 31 + usize::from(beam) * 17) % 101) as f64 / 50.0 - 1.0);
            positions.push(SENSOR + direction * (range + jitter));
            rings.push(beam);
        }
    }
    (positions, rings)
}

/// The origin of a patch whose support holds `probe` within `thickness` of its plane.
fn patch_at(patches: &PatchSet, decoded: &[Patch], probe: DVec3, thickness: f32) -> Option<DVec3> {
    let local = (probe - patches.offset).as_vec3();
    decoded
        .iter()
        .find(|patch| {
            let offset = patch.to_local(local);
            patch.supports(Vec2::new(offset.x, offset.y)) && offset.z.abs() < thickness
        })
        .map(|patch| patch.origin.as_dvec3() + patches.offset)
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
        let hit = patch_at(&patches, &decoded, probe, 0.05);
        assert!(hit.is_none(), "{probe} lies on a patch at {hit:?}");
    }
}

/// The road `z = 0` meets a kerb's face at `y = KERB_Y`, 15 cm high, and the sidewalk beyond.
const KERB_Y: f64 = 5.0;
const KERB_HEIGHT: f64 = 0.15;

/// A 32-beam sweep (as `sweep`) of the road, the kerb and the sidewalk, with range noise of
/// `noise` metres: within 8 m of the sensor each line lies metres from the next, and about one
/// line crosses the kerb's face.
fn kerb_sweep(noise: f64) -> PointCloud {
    let (positions, rings) =
        sweep_scene(noise, |direction| kerb_range(direction).filter(|&range| range < 12.0));
    PointCloud { positions, rings: Some(rings), sensor_position: Some(SENSOR), ..PointCloud::default() }
}

/// The range at which a ray from the sensor meets the road, the kerb's face or the sidewalk.
fn kerb_range(direction: DVec3) -> Option<f64> {
    if direction.z >= 0.0 {
        return None;
    }
    let road = -SENSOR.z / direction.z;
    if SENSOR.y + road * direction.y < KERB_Y {
        return Some(road);
    }
    let face = (KERB_Y - SENSOR.y) / direction.y;
    if SENSOR.z + face * direction.z <= KERB_HEIGHT {
        return Some(face);
    }
    Some((KERB_HEIGHT - SENSOR.z) / direction.z)
}

#[test]
fn a_kerbs_face_is_a_face_and_the_sidewalk_stops_at_its_edge() {
    let patches = prepped(&kerb_sweep(0.01), ScanMode::Auto);
    let decoded: Vec<_> = patches.hot.iter().map(|h| h.decode()).collect();
    let world = |origin: glam::Vec3| origin.as_dvec3() + patches.offset;
    // Nothing hangs over the road in front of the kerb's top edge.
    let overhang: Vec<DVec3> =
        (0..60).map(|i| DVec3::new(0.5 + 0.05 * i as f64, KERB_Y - 0.08, KERB_HEIGHT - 0.01)).collect();
    for probe in overhang {
        let hit = patch_at(&patches, &decoded, probe, 0.02);
        assert!(hit.is_none(), "{probe} lies on a patch at {hit:?}");
    }
    // The face's patches stand upright, not ramping from the road to the sidewalk.
    let on_face: Vec<_> = decoded
        .iter()
        .filter(|patch| {
            let at = world(patch.origin);
            (at.y - KERB_Y).abs() < 0.03 && at.z > 0.03 && at.z < 0.12 && at.x > 0.0
        })
        .collect();
    let upright = on_face.iter().filter(|patch| patch.frame.n.z.abs() < 0.5).count();
    assert!(on_face.len() > 20, "only {} patches on the kerb's face", on_face.len());
    assert!(upright * 4 >= on_face.len() * 3, "{upright} of {} face patches upright", on_face.len());
}

/// A return at the sensor itself (a KITTI sweep of gently waving ground whose corner is the
/// sensor) is a patch of some size, which the store can hold, not one of no size that it
/// refuses.
#[test]
fn a_return_at_its_sensor_makes_a_patch_of_some_size() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sweep.bin");
    let bytes: Vec<u8> = (0..1600)
        .flat_map(|i| {
            let (x, y) = ((i % 40) as f32 * 0.25, (i / 40) as f32 * 0.25);
            [x, y, 0.2 * (x * 0.7).sin(), 0.5].into_iter().flat_map(f32::to_le_bytes)
        })
        .collect();
    std::fs::write(&path, bytes).unwrap();
    let cloud = pointray_io::formats::read_point_cloud(&path).expect("the sweep");
    let (patches, report) = prep(&cloud, &PrepSettings::default(), &NoProgress).expect("prep");
    assert!(report.scan.is_some(), "the sweep's lines were not used");
    let stored = pointray_patches::patch_store::as_stored(&patches, &path.with_extension("patches"));
    assert!(stored.is_ok_and(|stored| stored.check().is_ok()), "the store refused the patches");
}
