//! The path integrator on the GPU: a white furnace, and agreement with the CPU's path
//! integrator. Both draw the same random numbers for a seed, so they follow the same paths
//! but where rounding decides otherwise; the bound on their difference is computed from two
//! CPU renders with different seeds, which differ by the Monte Carlo noise alone.

use std::sync::Arc;

use crate::common;

use common::{assert_no_validation_messages, floor, mesh, object, patches, renderer, sphere_patches};
use glam::Vec3;
use pointray_scene::{
    Background, Camera, Geometry, Integrator, Light, Material, RenderSettings, RenderedImage, Scene, SunSky,
    SurfaceKind,
};
use pointray_test_support::analytic_scenes::path_settings;
use pointray_test_support::estimate;

fn material(surface: SurfaceKind, color: Vec3, roughness: f32) -> Material {
    Material { surface, diffuse: color, roughness, ..Material::default() }
}

fn camera() -> Camera {
    Camera {
        position: Vec3::new(0.0, 2.0, 4.5),
        look_at: Vec3::new(0.0, 0.8, 0.0),
        up: Vec3::Y,
        vertical_fov_degrees: 45.0,
    }
}

/// A rough plastic point-set sphere and a glass one on a diffuse floor, under a quad light,
/// a sphere light and a sky: every BSDF kind but the conductor's, every light sampled.
fn lit_scene() -> Scene {
    let quad = Light::Quad {
        corner: Vec3::new(-1.0, 3.5, -1.0),
        edge_u: Vec3::new(0.0, 0.0, 2.0),
        edge_v: Vec3::new(2.0, 0.0, 0.0),
        color: Vec3::ONE,
        intensity: 4.0,
    };
    let bulb = Light::Sphere {
        center: Vec3::new(2.0, 2.0, 1.0),
        radius: 0.3,
        color: Vec3::new(1.0, 0.8, 0.6),
        intensity: 6.0,
    };
    Scene {
        camera: camera(),
        lights: vec![quad, bulb],
        background: Background::Gradient { top: Vec3::new(0.2, 0.3, 0.5), bottom: Vec3::splat(0.1) },
        objects: vec![
            object(
                "plastic",
                patches(sphere_patches(Vec3::new(-0.7, 0.7, 0.0), 0.7, 3000)),
                material(SurfaceKind::Plastic, Vec3::new(0.8, 0.3, 0.2), 0.2),
            ),
            object(
                "metal",
                patches(sphere_patches(Vec3::new(0.8, 0.5, 0.6), 0.5, 2000)),
                material(SurfaceKind::Conductor, Vec3::new(0.9, 0.8, 0.5), 0.3),
            ),
            object(
                "glass",
                patches(sphere_patches(Vec3::new(0.6, 0.5, -0.8), 0.5, 2000)),
                material(SurfaceKind::Dielectric, Vec3::ONE, 0.0),
            ),
            object("floor", mesh(floor(0.0, 4.0)), material(SurfaceKind::Diffuse, Vec3::splat(0.6), 0.0)),
        ],
    }
}

/// The mean over pixels and channels of |a - b| / (b + 0.05): relative, with dark pixels
/// measured against 0.05 so that noise on black does not dominate.
fn mean_relative_error(a: &RenderedImage, b: &RenderedImage) -> f64 {
    let sum: f64 = a
        .color
        .iter()
        .zip(&b.color)
        .map(|(x, y)| f64::from(((*x - *y).abs() / (*y + Vec3::splat(0.05))).element_sum()) / 3.0)
        .sum();
    sum / a.color.len() as f64
}

/// Renders `scene` on both backends and requires that they differ by no more than two CPU
/// renders of different seeds do; returns both images.
fn assert_backends_agree(
    renderer: &pointray_vulkan::VulkanRenderer,
    scene: &Scene,
    settings: &RenderSettings,
) -> (RenderedImage, RenderedImage) {
    let gpu = renderer.render(scene, settings).expect("the Vulkan backend path traces");
    assert_no_validation_messages(renderer);
    let cpu = pointray_cpu::render(scene, settings);
    let other_seed = pointray_cpu::render(scene, &RenderSettings { seed: settings.seed + 1, ..*settings });
    let noise = mean_relative_error(&other_seed, &cpu);
    let error = mean_relative_error(&gpu, &cpu);
    eprintln!("mean relative error: GPU against CPU {error:.5}, CPU against CPU of another seed {noise:.5}");
    assert!(noise > 0.0, "two seeds gave one image");
    assert!(error <= noise, "the GPU differs from the CPU by {error:.5}, more than the noise ({noise:.5})");
    // And the images' means agree within the noise of their pixels.
    let differences = |x: &RenderedImage| -> Vec<f64> {
        x.color.iter().zip(&cpu.color).map(|(a, b)| f64::from((*a - *b).element_sum()) / 3.0).collect()
    };
    let spread = estimate(differences(&other_seed)).standard_error;
    let offset = estimate(differences(&gpu)).mean;
    assert!(offset.abs() <= 5.0 * spread, "mean GPU - CPU {offset:.5} beyond 5 x {spread:.5}");
    (gpu, cpu)
}

#[test]
fn gpu_and_cpu_path_tracing_agree_within_the_noise() {
    let Some(renderer) = renderer() else { return };
    let scene = lit_scene();
    let settings = path_settings(32, 32, 5, 7);
    let (gpu, cpu) = assert_backends_agree(&renderer, &scene, &settings);
    // The albedo AOV: the CPU's in f32, the GPU's in half floats (a relative 2^-11).
    let (cpu_albedo, gpu_albedo) =
        (cpu.albedo.as_ref().unwrap(), gpu.albedo.as_ref().expect("the GPU's albedo"));
    let albedo_agrees =
        (0..cpu.pixel_count()).filter(|&i| cpu.instance_id[i] == gpu.instance_id[i]).all(|i| {
            (cpu_albedo[i] - gpu_albedo[i]).abs().max_element()
                <= 1e-3 * cpu_albedo[i].max_element().max(1e-3)
        });
    assert!(albedo_agrees, "the albedo AOVs differ beyond half precision");
    let whitted = RenderSettings { integrator: Integrator::Whitted, ..settings };
    assert_eq!(renderer.render(&scene, &whitted).expect("Whitted renders").albedo, None);
    let ids_agree = (0..cpu.pixel_count()).filter(|&i| cpu.instance_id[i] == gpu.instance_id[i]).count();
    assert!(
        ids_agree as f64 >= 0.99 * cpu.pixel_count() as f64,
        "{ids_agree} of {} ids agree",
        cpu.pixel_count()
    );
}

/// A white closed surface in a white furnace is white on the GPU.
fn assert_gpu_furnace(sphere: Geometry, what: &str) {
    let Some(renderer) = renderer() else { return };
    let white = material(SurfaceKind::Diffuse, Vec3::ONE, 0.0);
    let scene = Scene {
        camera: Camera { position: Vec3::new(0.0, 0.5, 3.0), look_at: Vec3::ZERO, ..camera() },
        lights: vec![],
        background: Background::Solid(Vec3::ONE),
        objects: vec![object("sphere", sphere, white)],
    };
    let image =
        renderer.render(&scene, &path_settings(32, 16, 6, 3)).expect("the Vulkan backend path traces");
    assert_no_validation_messages(&renderer);
    let hits: Vec<f64> = (0..image.pixel_count())
        .filter(|&i| image.instance_id[i] != RenderedImage::MISS)
        .map(|i| f64::from(image.color[i].y))
        .collect();
    assert!(hits.len() > image.pixel_count() / 4);
    estimate(hits).assert_near(1.0, 5.0, 1e-4, what);
}

#[test]
fn a_white_point_set_sphere_in_a_white_furnace_is_white_on_the_gpu() {
    assert_gpu_furnace(patches(sphere_patches(Vec3::ZERO, 1.0, 4000)), "GPU furnace, point-set sphere");
}

#[test]
fn a_white_mesh_sphere_in_a_white_furnace_is_white_on_the_gpu() {
    assert_gpu_furnace(mesh(pointray_test_support::sphere_mesh(1.0, 24, 48)), "GPU furnace, mesh sphere");
}

#[test]
fn gpu_and_cpu_agree_under_an_environment_map_drawn_by_its_radiance() {
    let Some(renderer) = renderer() else { return };
    let sun_and_sky = SunSky {
        sun_elevation_degrees: 40.0,
        sun_azimuth_degrees: 200.0,
        sun_radius_degrees: 3.0,
        sun_intensity: 5.0,
        sky_intensity: 1.0,
    };
    let map = sun_and_sky.map();
    let scene = Scene { lights: vec![], background: Background::Map(Arc::new(map)), ..lit_scene() };
    let (gpu, _) = assert_backends_agree(&renderer, &scene, &path_settings(32, 32, 5, 11));
    // Rays that miss show the map: the sky above the floor's far edge is blue.
    let sky = (0..gpu.pixel_count()).find(|&i| gpu.instance_id[i] == RenderedImage::MISS);
    let sky = gpu.color[sky.expect("a pixel of sky")];
    assert!(sky.z > sky.x && sky.z > 0.3, "{sky}");
}

/// Seen from inside, a closed point-set sphere under a white sky is black on the GPU too: no
/// bounce or shadow ray slips out through a wall it meets at a grazing angle.
#[test]
fn no_light_leaks_into_a_closed_point_set_sphere_on_the_gpu() {
    let Some(renderer) = renderer() else { return };
    let white = material(SurfaceKind::Diffuse, Vec3::ONE, 0.0);
    let sphere = object("sphere", patches(sphere_patches(Vec3::ZERO, 1.0, 6000)), white);
    for look_at in [Vec3::X, Vec3::new(0.3, 1.0, 0.2)] {
        let scene = Scene {
            camera: Camera { position: Vec3::ZERO, look_at, up: Vec3::Y, vertical_fov_degrees: 100.0 },
            lights: vec![],
            background: Background::Solid(Vec3::ONE),
            objects: vec![sphere.clone()],
        };
        let image =
            renderer.render(&scene, &path_settings(32, 16, 5, 3)).expect("the Vulkan backend path traces");
        assert_no_validation_messages(&renderer);
        assert!(
            image.instance_id.iter().all(|&id| id != RenderedImage::MISS),
            "a ray left the sphere unseen"
        );
        let lit = image.color.iter().filter(|c| c.max_element() > 0.0).count();
        assert_eq!(lit, 0, "light leaks into {lit} pixels looking at {look_at}");
    }
}

/// An emissive mesh panel as the only light: light sampling draws its triangles on both
/// backends alike.
#[test]
fn gpu_and_cpu_agree_under_an_emissive_mesh() {
    let Some(renderer) = renderer() else { return };
    let (corner, edge_u, edge_v) =
        (Vec3::new(-1.0, 3.0, -1.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 2.0));
    let panel = pointray_io::TriangleMesh {
        positions: vec![corner, corner + edge_u, corner + edge_u + edge_v, corner + edge_v],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    };
    let glowing = Material { emission: Vec3::splat(4.0), ..material(SurfaceKind::Diffuse, Vec3::ZERO, 0.0) };
    let mut scene = Scene { lights: vec![], background: Background::Solid(Vec3::ZERO), ..lit_scene() };
    scene.objects.push(object("panel", mesh(panel), glowing));
    let (gpu, _) = assert_backends_agree(&renderer, &scene, &path_settings(32, 32, 4, 13));
    let lit = gpu.color.iter().filter(|c| c.max_element() > 0.05).count();
    assert!(lit > gpu.pixel_count() / 4, "the panel lights the scene ({lit} pixels lit)");
}
