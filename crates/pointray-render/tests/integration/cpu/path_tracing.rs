//! The path integrator against cases whose answer is known: a white closed surface under a
//! white sky (the furnace: no energy lost, no light leaking between patches), a diffuse
//! plane under a uniform sky, a glass slab seen head on. Each tolerance is computed from the
//! render's own noise (`pointray_test_support::estimate`).

use std::sync::Arc;

use glam::{Affine3A, Quat, Vec3};
use pointray_cpu::CpuRenderer;
use pointray_kernels::EnvironmentMap;
use pointray_patches::{PatchSet, PrepSettings};
use pointray_scene::procedural::sphere_points;
use pointray_scene::{
    Background, Integrator, Material, RenderSettings, RenderedImage, Scene, SunSky, SurfaceKind,
};
use pointray_surface::{NoProgress, prep};
use pointray_test_support::analytic_scenes::*;
use pointray_test_support::{estimate, sphere_mesh};

/// Standard errors a mean may stray: a false failure once in 1.7 million runs.
const SIGMAS: f64 = 5.0;

/// The seed of every render here.
const SEED: u32 = 7;

fn diffuse(albedo: f32) -> Material {
    Material { surface: SurfaceKind::Diffuse, diffuse: Vec3::splat(albedo), ..Material::default() }
}

fn glass() -> Material {
    Material {
        surface: SurfaceKind::Dielectric,
        diffuse: Vec3::ONE,
        roughness: 0.0,
        ior: 1.5,
        ..Material::default()
    }
}

fn under_sky(objects: Vec<pointray_scene::SceneObject>, sky: Background, from: Vec3, fov: f32) -> Scene {
    let camera = pointray_scene::Camera { vertical_fov_degrees: fov, ..camera(from, Vec3::ZERO) };
    Scene { background: sky, ..scene(camera, vec![], objects) }
}

/// The green channel of every pixel whose primary ray hit an object.
fn hit_values(image: &RenderedImage) -> Vec<f64> {
    let hits: Vec<f64> = (0..image.pixel_count())
        .filter(|&i| image.instance_id[i] != RenderedImage::MISS)
        .map(|i| f64::from(image.color[i].y))
        .collect();
    assert!(hits.len() > image.pixel_count() / 4, "the object should fill much of the image");
    hits
}

/// A furnace: every pixel of a white closed surface under a white sky is 1 in expectation;
/// paths that leak inside the surface never see the sky and are cut by `max_depth`.
fn assert_furnace(object: pointray_scene::SceneObject, sky: Background, what: &str) {
    let scene = under_sky(vec![object], sky, Vec3::new(0.0, 0.5, 3.0), 45.0);
    let image = CpuRenderer::new(&scene).render(&path_settings(32, 16, 6, SEED));
    let values = hit_values(&image);
    let e = estimate(values.iter().copied());
    e.assert_near(1.0, SIGMAS, 1e-4, what);
    // A leak darkens a seam, not the whole sphere: no pixel may stray far below 1.
    let darkest = values.iter().copied().fold(f64::INFINITY, f64::min);
    let pixel_sigma = e.standard_error * (e.count as f64).sqrt();
    assert!(
        darkest > 1.0 - 8.0 * pixel_sigma - 1e-3,
        "{what}: a pixel of {darkest:.4} (pixel sigma {pixel_sigma:.4})"
    );
}

#[test]
fn a_white_mesh_sphere_in_a_white_furnace_is_white() {
    let sphere = mesh_object("sphere", sphere_mesh(1.0, 24, 48), diffuse(1.0));
    assert_furnace(sphere, Background::Solid(Vec3::ONE), "mesh sphere");
}

/// A scanned sphere: points with 1% radial noise, prepped with their normals recomputed, so
/// that neighbouring patches overlap unevenly as on a real scan.
fn noisy_sphere_patches(count: u32) -> PatchSet {
    let mut cloud = sphere_points(Vec3::ZERO, 1.0, count);
    for (i, position) in cloud.positions.iter_mut().enumerate() {
        let noise = ((i as f64 * 12.9898).sin() * 43_758.545_3).fract();
        *position *= 1.0 + 0.01 * noise;
    }
    let settings = PrepSettings { recompute_normals: true, ..PrepSettings::default() };
    prep(&cloud, &settings, &NoProgress).expect("a sphere preps").0
}

#[test]
fn a_white_point_set_sphere_in_a_white_furnace_is_white() {
    let sphere = patches_object("sphere", noisy_sphere_patches(3000), Affine3A::IDENTITY, diffuse(1.0));
    assert_furnace(sphere, Background::Solid(Vec3::ONE), "point-set sphere");
}

/// A white map, drawn from by its own distribution rather than uniformly: still a furnace.
#[test]
fn a_white_point_set_sphere_under_a_white_environment_map_is_white() {
    let white = EnvironmentMap::new(64, 32, &[Vec3::ONE; 64 * 32], 0.3);
    let sphere = patches_object("sphere", noisy_sphere_patches(3000), Affine3A::IDENTITY, diffuse(1.0));
    assert_furnace(sphere, Background::Map(Arc::new(white)), "point-set sphere under a map");
}

/// The irradiance that a map gives a surface facing up, integrated texel by texel: each
/// texel of the upper half covers `2π / width` in azimuth and contributes
/// `∫ cos θ sin θ dθ = (sin² θ1 - sin² θ0) / 2` over its row.
fn irradiance_from_above(map: &EnvironmentMap) -> f64 {
    let (width, height) = (map.width() as usize, map.height() as usize);
    let mut sum = 0.0;
    for y in 0..height / 2 {
        let angle = |row: usize| std::f64::consts::PI * row as f64 / height as f64;
        let band = 0.5 * (angle(y + 1).sin().powi(2) - angle(y).sin().powi(2));
        let row: f64 = map.texels()[y * width..(y + 1) * width].iter().map(|t| f64::from(t[1])).sum();
        sum += row * band * std::f64::consts::TAU / width as f64;
    }
    sum
}

#[test]
fn a_diffuse_plane_under_a_sun_and_sky_reflects_the_irradiance_the_map_holds() {
    let albedo = 0.6;
    let sun_and_sky = SunSky {
        sun_elevation_degrees: 50.0,
        sun_azimuth_degrees: 70.0,
        sun_radius_degrees: 1.5,
        sun_intensity: 6.0,
        sky_intensity: 1.0,
    };
    let map = Arc::new(sun_and_sky.map());
    let expected = f64::from(albedo) * irradiance_from_above(&map) / std::f64::consts::PI;
    let plane = patches_object("plane", plane_patches(1.0, 41), Affine3A::IDENTITY, diffuse(albedo));
    let scene = under_sky(vec![plane], Background::Map(map), Vec3::new(0.2, 2.0, 0.6), 30.0);
    let image = CpuRenderer::new(&scene).render(&path_settings(24, 8, 3, SEED));
    let values = hit_values(&image);
    let e = estimate(values.iter().copied());
    e.assert_near(expected, SIGMAS, 1e-4, "plane under the sun and sky");
    // Drawn by its radiance, the sun is found by most light samples. The BSDF's draws alone
    // would find its 0.002 sr once in about 2000 tries, leaving a pixel of 8 samples with a
    // noise of several times its mean; the map's own draws keep it under a third.
    let pixel_sigma = e.standard_error * (e.count as f64).sqrt();
    assert!(pixel_sigma < 0.3 * expected, "pixel noise {pixel_sigma:.4} against {expected:.4}");
}

#[test]
fn a_diffuse_plane_under_a_uniform_sky_shows_its_albedo() {
    let albedo = 0.45;
    let sky = Background::Solid(Vec3::ONE);
    let from = Vec3::new(0.2, 2.0, 0.6);
    for (object, what) in [
        (
            patches_object("plane", plane_patches(1.0, 41), Affine3A::IDENTITY, diffuse(albedo)),
            "point-set plane",
        ),
        (mesh_object("plane", floor_mesh(1.0), diffuse(albedo)), "mesh plane"),
    ] {
        let renderer = CpuRenderer::new(&under_sky(vec![object], sky.clone(), from, 30.0));
        let image = renderer.render(&path_settings(24, 8, 4, SEED));
        estimate(hit_values(&image)).assert_near(f64::from(albedo), SIGMAS, 1e-4, what);
        // The albedo AOV is the plane's colour where it was hit, zero elsewhere.
        let aov = image.albedo.as_ref().expect("the path integrator writes the albedo");
        for (index, &id) in image.instance_id.iter().enumerate() {
            let expected = if id == RenderedImage::MISS { Vec3::ZERO } else { Vec3::splat(albedo) };
            assert_eq!(aov[index], expected, "{what}: albedo at pixel {index}");
        }
        let whitted = RenderSettings { integrator: Integrator::Whitted, ..path_settings(4, 1, 2, SEED) };
        assert_eq!(renderer.render(&whitted).albedo, None);
    }
}

/// Looking straight down through a glass slab at a sky that is 1 below and 0 above: what
/// comes through is the slab's transmittance with every inner reflection,
/// `(1 - R) / (1 + R)` for R = ((n - 1) / (n + 1))², the 1/n² of radiance entering undone on
/// the way out, times the sky in the pixel's direction (a slab lets rays out parallel).
#[test]
fn a_glass_slab_head_on_transmits_as_fresnel_says() {
    let reflectance = (0.5f64 / 2.5).powi(2);
    let transmittance = (1.0 - reflectance) / (1.0 + reflectance);
    let below = Background::Gradient { top: Vec3::ZERO, bottom: Vec3::ONE };
    let flip = Affine3A::from_rotation_translation(
        Quat::from_rotation_x(std::f32::consts::PI),
        Vec3::new(0.0, -0.2, 0.0),
    );
    let point_slab = vec![
        patches_object("top", plane_patches(1.0, 41), Affine3A::IDENTITY, glass()),
        patches_object("bottom", plane_patches(1.0, 41), flip, glass()),
    ];
    let mut bottom_mesh = floor_mesh(1.0);
    bottom_mesh.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    bottom_mesh.positions.iter_mut().for_each(|p| p.y = -0.2);
    let mesh_slab =
        vec![mesh_object("top", floor_mesh(1.0), glass()), mesh_object("bottom", bottom_mesh, glass())];
    let size = 24;
    for (objects, what) in [(point_slab, "point-set slab"), (mesh_slab, "mesh slab")] {
        let scene = under_sky(objects, below.clone(), Vec3::new(0.0, 1.0, 1e-3), 6.0);
        let sky: f64 = (0..size * size)
            .map(|i| {
                f64::from(
                    1.0 - 0.5 * (pixel_ray(&scene.camera, size, size, i % size, i / size).direction.y + 1.0),
                )
            })
            .sum::<f64>()
            / f64::from(size * size);
        let image = CpuRenderer::new(&scene).render(&path_settings(size, 64, 24, SEED));
        // The slack: Fresnel's change over the 4 degrees from the axis, and the jitter's.
        estimate(hit_values(&image)).assert_near(transmittance * sky, SIGMAS, 1e-4, what);
    }
}

#[test]
fn one_seed_gives_one_image_and_another_seed_another() {
    let sphere = patches_object("sphere", sphere_patches(1.0, 2000), Affine3A::IDENTITY, diffuse(0.7));
    let scene = under_sky(vec![sphere], Background::Solid(Vec3::ONE), Vec3::new(0.0, 0.5, 3.0), 45.0);
    let renderer = CpuRenderer::new(&scene);
    let settings = path_settings(16, 2, 4, SEED);
    assert_eq!(renderer.render(&settings), renderer.render(&settings));
    assert_ne!(
        renderer.render(&settings).color,
        renderer.render(&RenderSettings { seed: 8, ..settings }).color
    );
}

#[test]
fn renders_that_continue_one_another_average_to_one_render_of_all_their_samples() {
    let sphere = patches_object("sphere", sphere_patches(1.0, 2000), Affine3A::IDENTITY, diffuse(0.7));
    let scene = under_sky(vec![sphere], Background::Solid(Vec3::ONE), Vec3::new(0.0, 0.5, 3.0), 45.0);
    let renderer = CpuRenderer::new(&scene);
    let pass = |first_sample, samples_per_pixel| {
        renderer.render(&RenderSettings { first_sample, samples_per_pixel, ..path_settings(16, 1, 4, SEED) })
    };
    let (early, late, all) = (pass(0, 4), pass(4, 8), pass(0, 12));
    for ((a, b), whole) in early.color.iter().zip(&late.color).zip(&all.color) {
        let mean = (*a * 4.0 + *b * 8.0) / 12.0;
        assert!((mean - *whole).abs().max_element() <= 1e-5 * whole.max_element().max(1.0), "{mean} {whole}");
    }
    assert_ne!(late.color, pass(0, 8).color, "a later pass draws other samples");
    assert_eq!(late.depth, pass(4, 1).depth, "a pass's AOVs come from its first sample");
}

/// An emissive mesh panel lights a floor as a quad light of the same radiance does, and light
/// sampling finds it: both converge to one image, with noise of the same order.
#[test]
fn an_emissive_mesh_lights_the_floor_as_a_quad_light_of_its_radiance() {
    let (corner, edge_u, edge_v) =
        (Vec3::new(-0.3, 1.0, -0.3), Vec3::new(0.6, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.6));
    let quad = pointray_scene::Light::Quad { corner, edge_u, edge_v, color: Vec3::ONE, intensity: 5.0 };
    let panel = pointray_io::TriangleMesh {
        positions: vec![corner, corner + edge_u, corner + edge_u + edge_v, corner + edge_v],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    };
    let glowing = Material { emission: Vec3::splat(5.0), diffuse: Vec3::ZERO, ..diffuse(0.0) };
    let floor = || mesh_object("floor", floor_mesh(1.0), diffuse(0.5));
    let view = |objects, lights| {
        let camera = pointray_scene::Camera {
            vertical_fov_degrees: 40.0,
            ..camera(Vec3::new(0.0, 0.6, 2.5), Vec3::ZERO)
        };
        Scene { background: Background::Solid(Vec3::ZERO), ..scene(camera, lights, objects) }
    };
    let settings = path_settings(24, 64, 3, SEED);
    let by_light = CpuRenderer::new(&view(vec![floor()], vec![quad])).render(&settings);
    let by_mesh = CpuRenderer::new(&view(vec![floor(), mesh_object("panel", panel, glowing)], vec![]))
        .render(&settings);
    let floor_pixels = |image: &RenderedImage| -> Vec<f64> {
        (0..image.pixel_count())
            .filter(|&i| image.instance_id[i] == 0)
            .map(|i| f64::from(image.color[i].y))
            .collect()
    };
    let (light, mesh) = (estimate(floor_pixels(&by_light)), estimate(floor_pixels(&by_mesh)));
    let spread = (light.standard_error.powi(2) + mesh.standard_error.powi(2)).sqrt();
    assert!(
        (light.mean - mesh.mean).abs() < SIGMAS * spread + 1e-3,
        "quad light {light:?}, emissive mesh {mesh:?}"
    );
    assert!(
        mesh.standard_error < 2.0 * light.standard_error,
        "light sampling misses the mesh: {mesh:?} against {light:?}"
    );
}
