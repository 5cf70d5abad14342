//! Point colours interpolated at the hit on the GPU: a prepped, coloured sphere
//! (turned, scaled and moved, so that the blend must work in object space) draws the same
//! image as on the CPU, and shows the colour field without steps between patches, where one
//! colour per patch shows them.

use std::sync::Arc;

use glam::{Affine3A, DVec3, Quat, Vec3};
use pointray_io::PointCloud;
use pointray_patches::{PatchSet, PrepSettings};
use pointray_scene::{
    Background, Camera, Geometry, Material, RenderSettings, RenderedImage, Scene, SceneObject,
};
use pointray_surface::{NoProgress, prep};
use pointray_test_support::floor_scenes::{floor, mesh, object, point_light, primary_ray, settings};
use pointray_test_support::{assert_no_validation_messages, vulkan_renderer};

/// The linear colour each point carries, from its input position: ramps along x and y.
fn color_field(input: DVec3) -> Vec3 {
    Vec3::new(0.5 + 0.45 * input.x as f32, 0.5 + 0.45 * input.y as f32, 0.3)
}

/// The sRGB bytes that decode to `color_field`, as a coloured scan would carry them.
fn srgb_bytes(linear: Vec3) -> [u8; 3] {
    let encode = |c: f32| if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    linear.to_array().map(|c| (encode(c) * 255.0).round().clamp(0.0, 255.0) as u8)
}

/// 4,000 points on the unit sphere (a Fibonacci spiral), coloured by `color_field`, prepped.
pub fn coloured_sphere() -> PatchSet {
    let count = 4000;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let positions: Vec<DVec3> = (0..count)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / count as f64;
            let ring = (1.0 - y * y).sqrt();
            let angle = golden * i as f64;
            DVec3::new(ring * angle.cos(), y, ring * angle.sin())
        })
        .collect();
    let colors = positions.iter().map(|&p| srgb_bytes(color_field(p))).collect();
    let cloud = PointCloud { colors: Some(colors), ..PointCloud::from_positions(positions) };
    prep(&cloud, &PrepSettings::default(), &NoProgress).expect("a sphere preps").0
}

fn placement() -> Affine3A {
    Affine3A::from_scale_rotation_translation(
        Vec3::splat(0.8),
        Quat::from_rotation_y(0.6),
        Vec3::new(0.2, 1.0, 0.0),
    )
}

fn sphere_object(patches: PatchSet, material: Material) -> SceneObject {
    SceneObject {
        name: "coloured sphere".into(),
        transform: placement(),
        material: Material { use_point_colors: true, specular: 0.0, ..material },
        geometry: Geometry::Patches(Arc::new(patches)),
    }
}

fn camera() -> Camera {
    Camera {
        position: Vec3::new(0.0, 1.8, 3.2),
        look_at: Vec3::new(0.1, 0.9, 0.0),
        up: Vec3::Y,
        vertical_fov_degrees: 40.0,
    }
}

/// No lights and full ambient: each pixel shows the interpolated colour itself.
fn unlit(patches: PatchSet) -> Scene {
    let material = Material { ambient: 1.0, reflectivity: 0.0, ..Material::default() };
    Scene {
        camera: camera(),
        lights: vec![],
        background: Background::Solid(Vec3::ZERO),
        objects: vec![sphere_object(patches, material)],
    }
}

/// Lit, over a reflective floor: the blend at primary and reflection hits, under shadows.
pub fn lit_on_floor(patches: PatchSet) -> Scene {
    let floor_material = Material { reflectivity: 0.4, ..Material::default() };
    Scene {
        camera: camera(),
        lights: vec![point_light(Vec3::new(2.0, 5.0, 2.0), 1.0)],
        background: Background::Gradient { top: Vec3::new(0.5, 0.7, 1.0), bottom: Vec3::ONE },
        objects: vec![
            sphere_object(patches, Material { reflectivity: 0.0, ..Material::default() }),
            object("floor", mesh(floor(0.0, 4.0)), floor_material),
        ],
    }
}

/// The largest step between neighbouring sphere pixels beyond what the colour field changes
/// between their hit points. Pixels at grazing angles (normal within 60 degrees of the
/// silhouette) are left out: there one pixel spans several patches anyway.
fn largest_step_beyond_the_field(image: &RenderedImage, patches: &PatchSet) -> f32 {
    let to_input = placement().inverse();
    let facing = |i: usize| {
        let ray = primary_ray(&camera(), image, i);
        image.instance_id[i] == 0 && image.normal[i].dot(-ray.direction) > 0.5
    };
    let field_at = |i: usize| {
        let world = primary_ray(&camera(), image, i).at(image.depth[i]);
        color_field(to_input.transform_point3(world).as_dvec3() + patches.offset)
    };
    let width = image.width as usize;
    let mut largest = 0.0f32;
    for here in 0..image.pixel_count() {
        let (right, below) = ((here % width + 1 < width).then_some(here + 1), Some(here + width));
        for next in [right, below].into_iter().flatten().filter(|&n| n < image.pixel_count()) {
            if facing(here) && facing(next) {
                let step = image.color[here] - image.color[next];
                largest = largest.max((step - (field_at(here) - field_at(next))).abs().max_element());
            }
        }
    }
    largest
}

#[test]
fn interpolated_colours_match_the_cpu_and_show_no_steps() {
    let Some(renderer) = vulkan_renderer() else { return };
    let patches = coloured_sphere();
    assert!(!patches.color_neighbors.is_empty(), "a coloured cloud keeps colour neighbours");
    let one_colour_per_patch = PatchSet { color_neighbors: Default::default(), ..patches.clone() };
    let settings = RenderSettings { max_depth: 1, ..settings(128) };
    let render_both = |set: PatchSet, name: &str| {
        let scene = unlit(set);
        let gpu = renderer.render(&scene, &settings).expect("the Vulkan backend renders");
        let psnr = pointray_cpu::render(&scene, &settings).color_psnr(&gpu);
        eprintln!("unlit coloured sphere, {name}: CPU against Vulkan {psnr:.1} dB");
        (gpu, psnr)
    };
    let (blended, blended_psnr) = render_both(patches.clone(), "interpolated");
    // One colour per patch depends on which of the overlapping patches a pixel hits, and the
    // backends break near-ties differently; the blend does not, so they agree.
    let (blocky, _) = render_both(one_colour_per_patch, "one colour per patch");
    assert!(blended_psnr >= 45.0, "CPU and Vulkan differ: PSNR {blended_psnr:.1} dB");
    let covered = blended.hit_mask().iter().filter(|&&hit| hit).count();
    assert!(covered > 128 * 128 / 5, "the sphere fills the view: {covered} pixels");
    let smooth = largest_step_beyond_the_field(&blended, &patches);
    let steps = largest_step_beyond_the_field(&blocky, &patches);
    eprintln!("largest step beyond the colour field: {smooth} interpolated, {steps} one colour per patch");
    // The control: one colour per patch steps by 0.051 with the cell radius's small patches
    // (more with the paper's), five times the blend's step.
    assert!(steps > 0.04, "one colour per patch shows steps: {steps}");
    assert!(smooth < 0.025, "interpolated colours step by {smooth} beyond the field");
    assert_no_validation_messages(&renderer);
}

#[test]
fn lit_coloured_sphere_over_a_mirror_floor_matches_the_cpu() {
    let Some(renderer) = vulkan_renderer() else { return };
    let scene = lit_on_floor(coloured_sphere());
    let settings = settings(128);
    let gpu = renderer.render(&scene, &settings).expect("the Vulkan backend renders");
    let cpu = pointray_cpu::render(&scene, &settings);
    let psnr = cpu.color_psnr(&gpu);
    eprintln!("lit coloured sphere over a mirror floor: CPU against Vulkan {psnr:.1} dB");
    assert!(psnr >= 45.0, "CPU and Vulkan differ: PSNR {psnr:.1} dB");
    assert_no_validation_messages(&renderer);
}

#[test]
fn combined_buffers_colour_as_split_buffers_do() {
    let Some(renderer) = vulkan_renderer() else { return };
    let scene = lit_on_floor(coloured_sphere());
    // Packed records both ways: the combined buffer holds those only.
    let split = RenderSettings { hot_records: Some(pointray_scene::HotRecords::Packed), ..settings(96) };
    let combined = RenderSettings { buffer_layout: pointray_scene::BufferLayout::Combined, ..split };
    let from_split = renderer.render(&scene, &split).expect("renders with split buffers");
    let from_combined = renderer.render(&scene, &combined).expect("renders with combined buffers");
    assert_eq!(from_combined.color, from_split.color, "the combined layout colours the points differently");
    assert_no_validation_messages(&renderer);
}
