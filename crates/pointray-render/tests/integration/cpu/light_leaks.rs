//! Light leaking into a closed scanned surface: seen from inside, a closed point-set shape
//! under a white sky, path traced, must be black. Every bounce and shadow ray leaving a patch
//! starts off it along its normal (`path_ray_offset`) and skips nothing, so a path inside may
//! not slip out through a nearby wall, at any angle: the sky reaches every wall at every
//! incidence, grazing included.

use glam::{Affine3A, Vec3};
use pointray_cpu::CpuRenderer;
use pointray_io::PointCloud;
use pointray_io::TriangleMesh;
use pointray_patches::{PatchSet, PrepSettings};
use pointray_scene::procedural::sphere_points;
use pointray_scene::{Background, Camera, Integrator, Material, RenderSettings, RenderedImage, SurfaceKind};
use pointray_surface::{NoProgress, prep, sample_mesh};
use pointray_test_support::analytic_scenes::*;

/// A unit cube's six faces, wound to face out.
fn cube_mesh() -> TriangleMesh {
    let corner =
        |i: u32| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32) * 2.0 - Vec3::ONE;
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let triangles = quads.iter().flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]]).collect();
    TriangleMesh { positions: (0..8).map(corner).collect(), triangles }
}

fn prepped(cloud: &PointCloud) -> PatchSet {
    prep(cloud, &PrepSettings::default(), &NoProgress).expect("the cloud preps").0
}

/// The share of pixels, seen from the centre of `patches` under a white sky, that any light
/// reaches, and the brightest of them.
fn leaks(patches: PatchSet) -> (f64, f32) {
    let white = Material { surface: SurfaceKind::Diffuse, diffuse: Vec3::ONE, ..Material::default() };
    let object = patches_object("closed", patches, Affine3A::IDENTITY, white);
    let settings = RenderSettings {
        width: 48,
        height: 48,
        samples_per_pixel: 16,
        max_depth: 5,
        integrator: Integrator::Path,
        seed: 3,
        ..RenderSettings::default()
    };
    let mut lit = 0;
    let mut brightest = 0.0f32;
    let mut pixels = 0;
    for look_at in [Vec3::X, Vec3::new(1.0, 1.0, 1.0), Vec3::new(-1.0, -1.0, 0.3), Vec3::new(0.2, 1.0, 0.1)] {
        let camera = Camera { vertical_fov_degrees: 100.0, ..camera(Vec3::ZERO, look_at) };
        let scene = pointray_scene::Scene {
            background: Background::Solid(Vec3::ONE),
            ..scene(camera, vec![], vec![object.clone()])
        };
        let image = CpuRenderer::new(&scene).render(&settings);
        assert!(image.instance_id.iter().all(|&id| id != RenderedImage::MISS), "a ray left the shape unseen");
        lit += image.color.iter().filter(|c| c.max_element() > 0.0).count();
        brightest = image.color.iter().fold(brightest, |m, c| m.max(c.max_element()));
        pixels += image.pixel_count();
    }
    (lit as f64 / pixels as f64, brightest)
}

#[test]
fn no_light_leaks_into_a_closed_point_set_sphere() {
    let (share, brightest) = leaks(prepped(&sphere_points(Vec3::ZERO, 1.0, 6000)));
    eprintln!("sphere: {:.4}% of pixels lit, brightest {brightest}", 100.0 * share);
    assert_eq!(share, 0.0, "light leaks in (brightest pixel {brightest})");
}

/// At a cube's edges and corners the patches fitted across the edge round it off, and the
/// point set itself has small gaps there that paths find: 1.7% of the pixels seen from inside
/// catch some light at 16 samples (1.0% with rays leaving from the surface's epsilon alone,
/// which the furnace's noisy sphere shadows itself at; 55% when rays skipped every hit
/// within a support radius, as the Whitted integrator's do).
#[test]
fn little_light_leaks_into_a_closed_point_set_cube_at_its_edges_and_corners() {
    let (share, brightest) = leaks(prepped(&sample_mesh(&cube_mesh(), 12_000, 1, true)));
    eprintln!("cube: {:.4}% of pixels lit, brightest {brightest}", 100.0 * share);
    assert!(share < 0.025, "light leaks into {:.2}% of the pixels (brightest {brightest})", 100.0 * share);
}
