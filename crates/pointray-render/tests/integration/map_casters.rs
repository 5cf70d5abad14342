//! A real sweep (data/scans/real/ouster_os1_32/scan00.bin, data/SOURCES.md) prepped into a
//! map and its own rays re-simulated in it by both backends' casters: the Vulkan ray list
//! (on lavapipe where there is no GPU, under the validation layer) must meet what the CPU's
//! BVHs meet.

use std::sync::Arc;

use glam::{DAffine3, DVec3};
use pointray_io::formats::read_point_cloud;
use pointray_lidar::{CasterAgreement, LidarScene, SweepRays, resimulate_from};
use pointray_patches::{PatchSet, PrepSettings};
use pointray_render::GpuMapCaster;
use pointray_surface::{NoProgress, prep};
use pointray_test_support::{data_file, vulkan_renderer};

/// Both casters trace f32 rays through the same patch intersection; their traversals differ,
/// so where overlapping patches lie within a hair of each other either may be met first.
const RANGE_TOLERANCE_M: f64 = 0.001;
/// The share of rays that must agree: the same hit or miss, and ranges within the tolerance.
const AGREEING_BAR: f64 = 0.999;
const MAX_RANGE_M: f64 = 200.0;

fn sweep_map() -> (Arc<PatchSet>, SweepRays) {
    let cloud = read_point_cloud(&data_file("scans/real/ouster_os1_32/scan00.bin")).expect("the sweep");
    let (patches, _) = prep(&cloud, &PrepSettings::default(), &NoProgress).expect("prep of the sweep");
    (Arc::new(patches), SweepRays::of_sweep(&cloud))
}

/// Three poses about the sensor's own: more casts (27,310 rays from each) than one launch
/// row of the ray list holds (65,536).
fn poses() -> Vec<DAffine3> {
    let moved = |metres: f64, degrees: f64| {
        DAffine3::from_rotation_z(degrees.to_radians())
            * DAffine3::from_translation(DVec3::new(metres, 0.0, 0.0))
    };
    vec![DAffine3::IDENTITY, moved(0.5, 5.0), moved(-1.0, -20.0)]
}

#[test]
fn the_vulkan_caster_meets_what_the_cpu_caster_meets_on_a_real_sweep() {
    let Some(renderer) = vulkan_renderer() else { return };
    let (patches, rays) = sweep_map();
    let cpu = LidarScene::from_patches(patches.clone()).expect("the CPU caster");
    let gpu = GpuMapCaster::new(&renderer, patches).expect("the map uploads");
    let reference = resimulate_from(&cpu, &poses(), &rays, MAX_RANGE_M).expect("the CPU casts");
    let cast = resimulate_from(&gpu, &poses(), &rays, MAX_RANGE_M).expect("the GPU casts");
    assert_eq!((cast.len(), reference.len()), (3, 3), "a sweep for each pose");
    let agreement = CasterAgreement::of(&cast.concat(), &reference.concat(), RANGE_TOLERANCE_M);
    println!("{agreement:?}");
    let hits = reference.iter().flatten().flatten().count();
    assert!(hits * 10 >= agreement.rays * 9, "only {hits} of {} rays hit the map", agreement.rays);
    assert!(
        agreement.agreeing_fraction >= AGREEING_BAR,
        "{:.3}% of rays agree: {agreement:?}",
        100.0 * agreement.agreeing_fraction
    );
    assert_eq!(renderer.validation_messages(), 0, "validation messages (printed above)");
}
