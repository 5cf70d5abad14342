//! Colour interpolation on a prepped scan: every patch that a ray meets at one
//! point of the surface gives that point the same colour, where one colour per patch shows
//! steps, and the neighbour lists that make it work survive prep.

use crate::common;

use glam::{DVec3, Vec3};
use pointray_kernels::interpolate_color::{COLOR_SUPPORT_SCALE, color_from_rgba8};
use pointray_kernels::{COLOR_NEIGHBORS, PatchAcceptance, Ray, interpolate_color, intersect_patch};
use pointray_patches::{PatchSet, PrepSettings, RadiusMode};
use pointray_surface::{NoProgress, prep};

/// A jittered height field with a smooth colour field (sRGB in the file, as scans carry it).
fn coloured_scan() -> PatchSet {
    let mut cloud = common::height_field(50, DVec3::new(3e5, -2e5, 10.0), |x, y| 0.2 * (2.0 * x).sin() * y);
    let byte = |v: f64| (v * 255.0).round().clamp(0.0, 255.0) as u8;
    let colors = cloud.positions.iter().map(|p| {
        let (x, y) = (p.x - 3e5, p.y + 2e5);
        [byte(0.5 + 0.5 * (3.0 * x).sin()), byte(0.5 + 0.4 * y), 128]
    });
    cloud.colors = Some(colors.collect());
    prep(&cloud, &PrepSettings::default(), &NoProgress).expect("a height field preps").0
}

/// The largest channel difference within a set of colours.
fn spread(colors: &[Vec3]) -> f32 {
    let max = colors.iter().fold(Vec3::splat(f32::MIN), |a, &c| a.max(c));
    let min = colors.iter().fold(Vec3::splat(f32::MAX), |a, &c| a.min(c));
    (max - min).max_element()
}

#[test]
fn every_patch_a_ray_meets_gives_the_same_colour() {
    let patches = coloured_scan();
    assert_eq!(patches.color_neighbors.len(), patches.len() * COLOR_NEIGHBORS);
    let (mut blended, mut own) = (Vec::new(), Vec::new());
    for s in 0..400 {
        let x = 1.5 * (common::jitter(10_000 + 2 * s) as f32);
        let y = 1.5 * (common::jitter(10_001 + 2 * s) as f32);
        let start = (DVec3::new(3e5 + f64::from(x), -2e5 + f64::from(y), 20.0) - patches.offset).as_vec3();
        let ray = Ray::new(start, Vec3::NEG_Z);
        let (mut at_point, mut per_patch) = (Vec::new(), Vec::new());
        for (i, patch) in patches.hot.iter().enumerate() {
            let Some(hit) = intersect_patch(&ray, &patch.decode(), 0.0, 100.0, PatchAcceptance::Disk) else {
                continue;
            };
            let color = interpolate_color(
                ray.at(hit.t),
                i as u32,
                &patches.hot,
                &patches.cold,
                &patches.color_neighbors,
            );
            at_point.push(color_from_rgba8(color));
            per_patch.push(patches.cold[i].color());
        }
        assert!(at_point.len() >= 2, "patches overlap: ray {s} met {}", at_point.len());
        blended.push(spread(&at_point));
        own.push(spread(&per_patch));
    }
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    let worst = blended.iter().copied().fold(0.0, f32::max);
    // One 8-bit step is 1/255 = 0.0039.
    assert!(mean(&own) > 0.03, "one colour per patch shows steps: mean {}", mean(&own));
    assert!(mean(&blended) < 0.001 && worst <= 2.0 / 255.0, "blended: mean {} worst {worst}", mean(&blended));
}

#[test]
fn colours_reach_the_papers_distance_whatever_the_radius() {
    let cloud = common::height_field(30, DVec3::ZERO, |x, y| 0.1 * x * y);
    let prepped = |radius_mode| {
        prep(&cloud, &PrepSettings { radius: radius_mode, ..PrepSettings::default() }, &NoProgress).unwrap().0
    };
    let (paper, cell) = (prepped(RadiusMode::Paper), prepped(RadiusMode::Cell));
    for (i, (p, c)) in paper.cold.iter().zip(&cell.cold).enumerate() {
        assert_eq!(p.color_reach, COLOR_SUPPORT_SCALE * paper.hot[i].radius(), "patch {i}");
        assert_eq!(c.color_reach, p.color_reach, "patch {i}: the cell radius changed the colour reach");
    }
    let shorter = cell.hot.iter().zip(&paper.hot).filter(|(c, p)| c.radius() < p.radius()).count();
    assert!(shorter > cell.len() / 2, "the cell radius shortened only {shorter} of {} disks", cell.len());
}
