//! The error the compact patch store adds, seen in an image: a prepped model rendered from
//! its store against the same model's full-precision patches in memory. Two bunnies, one
//! plain and one coloured by its points (colours, intensities and colour reach from the
//! store), on the CPU renderer at 160x160: PSNR >= 50 dB, object ids equal on >= 99.9% of
//! pixels.

use glam::{Affine3A, Vec3};
use pointray_cpu::render;
use pointray_io::formats::read_point_cloud;
use pointray_patches::{PatchSet, PrepSettings, patch_store};
use pointray_scene::{Light, Material, RenderSettings, RenderedImage};
use pointray_surface::{NoProgress, prep};
use pointray_test_support::analytic_scenes::*;
use pointray_test_support::data_file;

const SIZE: u32 = 160;

/// The bunny's patches, plain or with colours and intensities that vary over it.
fn bunny(coloured: bool) -> PatchSet {
    let mut cloud = read_point_cloud(&data_file("points/bunny.ply")).expect("the bunny reads");
    if coloured {
        let channel = |v: f64| (v.fract().abs() * 255.0) as u8;
        let colors = cloud.positions.iter().map(|p| [channel(p.x * 31.0), channel(p.y * 17.0), 90]).collect();
        cloud.colors = Some(colors);
        cloud.intensities = Some(cloud.positions.iter().map(|p| (p.z * 23.0).fract().abs() as f32).collect());
    }
    prep(&cloud, &PrepSettings::default(), &NoProgress).expect("the bunny preps").0
}

/// `patches` written to a compact store and read back.
fn through_the_store(patches: &PatchSet, dir: &std::path::Path) -> PatchSet {
    let path = dir.join("bunny.patches");
    patch_store::write(&path, patches).unwrap();
    patch_store::read(&path).unwrap()
}

fn render_pair(plain: PatchSet, coloured: PatchSet) -> RenderedImage {
    let coloured_material = Material { use_point_colors: true, specular: 0.3, shininess: 20.0, ..matte() };
    let objects = vec![
        patches_object("plain", plain, Affine3A::from_translation(Vec3::new(-0.09, 0.0, 0.0)), matte()),
        patches_object(
            "coloured",
            coloured,
            Affine3A::from_translation(Vec3::new(0.09, 0.0, 0.0)),
            coloured_material,
        ),
    ];
    let light =
        Light::Directional { direction: Vec3::new(-0.3, -1.0, -0.5), color: Vec3::ONE, intensity: 1.0 };
    let scene = scene(camera(Vec3::new(0.0, 0.05, 0.45), Vec3::ZERO), vec![light], objects);
    render(&scene, &RenderSettings { width: SIZE, height: SIZE, ..RenderSettings::default() })
}

#[test]
fn a_model_from_the_compact_store_renders_as_its_full_precision_patches() {
    let dir = tempfile::tempdir().unwrap();
    let (plain, coloured) = (bunny(false), bunny(true));
    let stored = render_pair(through_the_store(&plain, dir.path()), through_the_store(&coloured, dir.path()));
    let full = render_pair(plain, coloured);
    let psnr = stored.color_psnr(&full);
    let same_ids = stored.instance_id.iter().zip(&full.instance_id).filter(|(a, b)| a == b).count();
    let share = same_ids as f64 / full.pixel_count() as f64;
    let covered = full.hit_mask().iter().filter(|&&hit| hit).count();
    println!("compact against full: {psnr:.1} dB, object ids equal on {:.3}% of pixels", 100.0 * share);
    assert!(covered > full.pixel_count() / 10, "the bunnies cover only {covered} pixels");
    assert!(full.instance_id.contains(&0) && full.instance_id.contains(&1), "both bunnies in view");
    assert!(psnr >= 50.0, "{psnr:.1} dB");
    assert!(share >= 0.999, "object ids equal on {:.3}% of pixels", 100.0 * share);
}
