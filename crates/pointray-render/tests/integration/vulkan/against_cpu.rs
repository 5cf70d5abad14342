//! The CPU renderer and the Vulkan renderer draw the same images (the thresholds below):
//! hit masks agree on >= 99.9% of pixels, normals within 1 degree on >= 99% of the pixels
//! both hit, and the shaded images reach PSNR >= 40 dB.

use pointray_patches::BoxKind;
use pointray_scene::{Geometry, Material, PatchAcceptance, RenderSettings, RenderedImage, Scene, demo_scene};
use pointray_test_support::floor_scenes::{model_on_floor, settings, sphere_on_floor};
use pointray_test_support::{assert_no_validation_messages, prepped_points_with_boxes, vulkan_renderer};

struct Agreement {
    mask: f64,
    normals_within_one_degree: f64,
    psnr_db: f64,
}

fn agreement(cpu: &RenderedImage, gpu: &RenderedImage) -> Agreement {
    let pixels = cpu.pixel_count();
    let masks_equal = (0..pixels).filter(|&i| cpu.hit_mask()[i] == gpu.hit_mask()[i]).count();
    let both_hit: Vec<usize> = (0..pixels)
        .filter(|&i| cpu.instance_id[i] != RenderedImage::MISS && gpu.instance_id[i] != RenderedImage::MISS)
        .collect();
    let close = both_hit
        .iter()
        .filter(|&&i| cpu.normal[i].dot(gpu.normal[i]).clamp(-1.0, 1.0).acos().to_degrees() <= 1.0)
        .count();
    let squared_error: f64 = (0..pixels)
        .map(|i| {
            let difference = cpu.color[i].clamp(glam::Vec3::ZERO, glam::Vec3::ONE)
                - gpu.color[i].clamp(glam::Vec3::ZERO, glam::Vec3::ONE);
            f64::from(difference.length_squared()) / 3.0
        })
        .sum();
    let mse = squared_error / pixels as f64;
    Agreement {
        mask: masks_equal as f64 / pixels as f64,
        normals_within_one_degree: close as f64 / both_hit.len().max(1) as f64,
        psnr_db: if mse == 0.0 { f64::INFINITY } else { 10.0 * (1.0 / mse).log10() },
    }
}

fn assert_backends_agree(name: &str, scene: &Scene, settings: &RenderSettings) {
    let Some(renderer) = vulkan_renderer() else { return };
    let gpu = renderer.render(scene, settings).expect("the Vulkan backend renders");
    assert_images_agree(name, &pointray_cpu::render(scene, settings), &gpu);
    assert_no_validation_messages(&renderer);
}

/// The CPU's and the GPU's frames of one scene meet the thresholds above.
pub fn assert_images_agree(name: &str, cpu: &RenderedImage, gpu: &RenderedImage) {
    let agreement = agreement(cpu, gpu);
    eprintln!(
        "{name}: masks {:.4}%, normals {:.4}%, PSNR {:.1} dB",
        100.0 * agreement.mask,
        100.0 * agreement.normals_within_one_degree,
        agreement.psnr_db
    );
    assert!(agreement.mask >= 0.999, "{name}: hit masks agree on only {:.4}%", 100.0 * agreement.mask);
    assert!(
        agreement.normals_within_one_degree >= 0.99,
        "{name}: normals agree within 1 degree on only {:.4}%",
        100.0 * agreement.normals_within_one_degree
    );
    assert!(agreement.psnr_db >= 40.0, "{name}: PSNR {:.1} dB", agreement.psnr_db);
}

#[test]
fn the_procedural_demo_matches() {
    let scene = demo_scene().expect("the demo scene builds");
    assert_backends_agree("demo", &scene, &settings(160));
}

#[test]
fn a_reflective_floor_under_a_sphere_matches() {
    assert_backends_agree("sphere on a mirror-ish floor", &sphere_on_floor(0.5, 1.0), &settings(128));
}

/// The paper's pair (cube boxes, box test) and ours (tight boxes, disk test). The box test
/// with tight boxes is left out: a hit inside the cube but outside the tight box is found
/// only by rays that also enter the tight box, so there the backends may legitimately differ.
#[test]
fn the_bunny_on_a_floor_matches_with_both_acceptance_tests() {
    let path = pointray_test_support::data_file("points/bunny.ply");
    for (acceptance, box_kind) in
        [(PatchAcceptance::Box, BoxKind::Cube), (PatchAcceptance::Disk, BoxKind::Tight)]
    {
        let material = Material { reflectivity: 0.0, ..Material::default() };
        let bunny = prepped_points_with_boxes("bunny", &path, material, box_kind);
        let Geometry::Patches(patches) = &bunny.geometry else { unreachable!("prepped points are patches") };
        let bounds = patches.bounds().expect("the bunny has patches");
        let offset = patches.offset.as_vec3();
        let world = pointray_kernels::Aabb::new(
            glam::Vec3::from(bounds.min) + offset,
            glam::Vec3::from(bounds.max) + offset,
        );
        let scene = model_on_floor(bunny, world, 0.4);
        let settings = RenderSettings { acceptance, ..settings(160) };
        assert_backends_agree(&format!("bunny, {acceptance:?} test, {box_kind:?} boxes"), &scene, &settings);
    }
}
