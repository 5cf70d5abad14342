//! Point colours are interpolated at the hit: a plane coloured by two crossing
//! gradients shows no steps between adjacent pixels, where one colour per patch does.

use glam::{Affine3A, DVec3, Vec3};
use pointray_cpu::render;
use pointray_io::PointCloud;
use pointray_patches::{PatchSet, PrepSettings, RadiusMode};
use pointray_scene::{Camera, Light, Material, RenderSettings, RenderedImage};
use pointray_surface::{NoProgress, prep};
use pointray_test_support::analytic_scenes::*;

/// A deterministic value in [-0.5, 0.5).
fn jitter(i: u64) -> f64 {
    let z = i.wrapping_add(1).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 11;
    (z as f64 / (1u64 << 53) as f64).fract() - 0.5
}

/// The sRGB byte of a linear value, so that the file's colours are linear ramps once decoded.
fn srgb_byte(linear: f64) -> u8 {
    let encoded = if linear <= 0.003_130_8 { 12.92 * linear } else { 1.055 * linear.powf(1.0 / 2.4) - 0.055 };
    (encoded * 255.0).round().clamp(0.0, 255.0) as u8
}

/// A jittered grid of `side²` points on y = 0 over [-1, 1]², red rising along x and blue
/// along z, prepped as a scan would be.
fn gradient_plane(side: usize) -> PatchSet {
    gradient_plane_with(side, RadiusMode::default())
}

fn gradient_plane_with(side: usize, radius_mode: RadiusMode) -> PatchSet {
    let cell = 2.0 / side as f64;
    let positions: Vec<DVec3> = (0..side * side)
        .map(|i| {
            let x = -1.0 + cell * ((i % side) as f64 + 0.5 + 0.5 * jitter(2 * i as u64));
            let z = -1.0 + cell * ((i / side) as f64 + 0.5 + 0.5 * jitter(2 * i as u64 + 1));
            DVec3::new(x, 0.0, z)
        })
        .collect();
    let colors =
        positions.iter().map(|p| [srgb_byte(0.5 + 0.45 * p.x), 40, srgb_byte(0.5 + 0.45 * p.z)]).collect();
    let cloud = PointCloud { colors: Some(colors), ..PointCloud::from_positions(positions) };
    prep(&cloud, &PrepSettings { radius: radius_mode, ..PrepSettings::default() }, &NoProgress)
        .expect("a plane preps")
        .0
}

const SIZE: u32 = 160;

fn view() -> Camera {
    camera(Vec3::new(0.0, 2.2, 1.2), Vec3::ZERO)
}

fn render_plane(patches: PatchSet) -> RenderedImage {
    let material = Material { use_point_colors: true, ..matte() };
    let plane = patches_object("plane", patches, Affine3A::IDENTITY, material);
    let light = Light::Directional { direction: Vec3::NEG_Y, color: Vec3::ONE, intensity: 1.0 };
    let scene = scene(view(), vec![light], vec![plane]);
    render(&scene, &RenderSettings { width: SIZE, height: SIZE, ..RenderSettings::default() })
}

/// The colour the plane should show at `hit`: ambient 0.1 plus the overhead light's full
/// diffuse, times the linear colour ramps of `gradient_plane`.
fn expected(hit: Vec3) -> Vec3 {
    let green = (f64::from(srgb_byte(0.0)) / 255.0) as f32;
    1.1 * Vec3::new(0.5 + 0.45 * hit.x, 0.0, 0.5 + 0.45 * hit.z) + Vec3::new(0.0, 1.1 * green, 0.0)
}

/// The largest step between two neighbouring pixels beyond what the gradients themselves
/// change there: how far their difference departs from the expected colours' difference.
/// Only pixels on the plane within the points' extent count: beyond it, on the rim that
/// patches reach past the last points, no point's colour reaches and each takes its nearest
/// point's.
fn largest_step(image: &RenderedImage) -> f32 {
    let (width, height) = (image.width as usize, image.height as usize);
    let hit = |i: usize| {
        let ray = pixel_ray(&view(), SIZE, SIZE, (i % width) as u32, (i / width) as u32);
        ray.at(image.depth[i])
    };
    let on_plane = |i: usize| image.instance_id[i] == 0 && hit(i).x.abs() < 0.95 && hit(i).z.abs() < 0.95;
    let mut largest = 0.0f32;
    for y in 0..height {
        for x in 0..width {
            let here = y * width + x;
            for next in [(x + 1 < width).then_some(here + 1), (y + 1 < height).then_some(here + width)] {
                if let Some(next) = next.filter(|&next| on_plane(here) && on_plane(next)) {
                    let step = image.color[here] - image.color[next];
                    let gradient = expected(hit(here)) - expected(hit(next));
                    largest = largest.max((step - gradient).abs().max_element());
                }
            }
        }
    }
    largest
}

#[test]
fn a_gradient_plane_has_no_steps_between_patches() {
    let patches = gradient_plane(30);
    let one_colour_per_patch = PatchSet { color_neighbors: Default::default(), ..patches.clone() };
    let blended = render_plane(patches);
    let blocky = render_plane(one_colour_per_patch);
    assert!(
        blended.hit_mask().iter().filter(|&&hit| hit).count() > (SIZE * SIZE / 3) as usize,
        "the plane fills the view"
    );
    let (smooth_step, blocky_step) = (largest_step(&blended), largest_step(&blocky));
    eprintln!(
        "largest step between adjacent pixels: {smooth_step} interpolated, {blocky_step} one colour per patch"
    );
    // One point spacing changes the ramps by 0.03 (x 1.1 light), and which patch wins a pixel
    // is arbitrary: one colour per patch steps by several times that. The blend follows the
    // ramps to within its own unevenness (a weighted mean is flatter near the points than
    // between them) and the 8-bit rounding (0.004).
    assert!(blocky_step > 0.06, "one colour per patch shows steps: {blocky_step}");
    assert!(smooth_step < 0.025, "interpolated colours step by {smooth_step} beyond the gradients");
}

#[test]
fn the_blend_follows_the_gradients_whatever_the_radius() {
    // The cell radius gives disks about half the paper's; the colour still reaches the
    // paper's distance (`PatchCold::color_reach`), so the blend is as smooth. Reaching only
    // 0.75 of the cell radius, it stepped by 0.046.
    for mode in [RadiusMode::Paper, RadiusMode::Cell] {
        let step = largest_step(&render_plane(gradient_plane_with(30, mode)));
        eprintln!("{mode:?} radius: largest step {step}");
        assert!(step < 0.025, "{mode:?} radius: interpolated colours step by {step}");
    }
}
