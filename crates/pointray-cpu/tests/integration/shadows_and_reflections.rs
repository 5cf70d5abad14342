//! Secondary rays: a sphere of patches over a triangle floor, lit from above.

use crate::common;

use common::*;
use glam::{Affine3A, Vec3};
use pointray_cpu::CpuRenderer;
use pointray_kernels::Ray;
use pointray_scene::{Light, Material, RenderSettings, RenderedImage, Scene};

const SPHERE_CENTRE: Vec3 = Vec3::new(0.0, 1.0, 0.0);
const SPHERE_RADIUS: f32 = 0.5;
const LIGHT: Vec3 = Vec3::new(0.3, 4.0, 0.2);
const SIZE: u32 = 80;
/// Ambient 0.1 times the matte diffuse 0.8.
const AMBIENT: f32 = 0.08;

fn floor_and_sphere(floor_material: Material, lights: Vec<Light>) -> Scene {
    let sphere = patches_object(
        "sphere",
        sphere_patches(SPHERE_RADIUS, 3000),
        Affine3A::from_translation(SPHERE_CENTRE),
        matte(),
    );
    let floor = mesh_object("floor", floor_mesh(3.0), floor_material);
    scene(camera(Vec3::new(0.0, 3.0, 4.0), Vec3::new(0.0, 0.3, 0.0)), lights, vec![floor, sphere])
}

fn point_light() -> Vec<Light> {
    vec![Light::point(LIGHT, Vec3::ONE, 1.0)]
}

fn settings() -> RenderSettings {
    RenderSettings { width: SIZE, height: SIZE, ..RenderSettings::default() }
}

/// Floor pixels the camera sees directly: `(pixel index, floor point, primary ray)`.
fn floor_pixels(scene: &Scene, image: &RenderedImage) -> Vec<(usize, Vec3, Ray)> {
    let mut pixels = Vec::new();
    for y in 0..SIZE {
        for x in 0..SIZE {
            let ray = pixel_ray(&scene.camera, SIZE, SIZE, x, y);
            let t = -ray.origin.y / ray.direction.y;
            let point = ray.at(t);
            let in_view_of_sphere =
                distance_to_line(SPHERE_CENTRE, ray.origin, ray.direction) < 1.3 * SPHERE_RADIUS;
            if t > 0.0 && point.x.abs() < 2.9 && point.z.abs() < 2.9 && !in_view_of_sphere {
                let index = (y * SIZE + x) as usize;
                assert_eq!(image.instance_id[index], 0, "expected the floor at ({x}, {y})");
                pixels.push((index, point, ray));
            }
        }
    }
    pixels
}

fn distance_to_line(point: Vec3, origin: Vec3, direction: Vec3) -> f32 {
    let along = (point - origin).dot(direction.normalize());
    (point - origin - along * direction.normalize()).length()
}

/// How far the segment from a floor point to the light passes from the sphere's centre.
fn shadow_clearance(floor_point: Vec3) -> f32 {
    distance_to_line(SPHERE_CENTRE, floor_point, LIGHT - floor_point)
}

#[test]
fn the_sphere_shadows_the_floor_exactly_where_the_geometry_says() {
    let scene = floor_and_sphere(matte(), point_light());
    let image = CpuRenderer::new(&scene).render(&settings());
    let (mut shadowed, mut lit) = (0, 0);
    for (index, point, _) in floor_pixels(&scene, &image) {
        let clearance = shadow_clearance(point);
        let brightness = image.color[index].x;
        if clearance < 0.9 * SPHERE_RADIUS {
            shadowed += 1;
            assert!((brightness - AMBIENT).abs() < 1e-5, "shadowed floor at {point} has {brightness}");
        } else if clearance > 1.2 * SPHERE_RADIUS {
            lit += 1;
            assert!(brightness > AMBIENT + 0.1, "lit floor at {point} has only {brightness}");
        }
    }
    assert!(shadowed > 20 && lit > 1000, "shadowed {shadowed}, lit {lit}");
}

#[test]
fn without_shadow_rays_or_without_the_light_the_shadow_disappears() {
    let no_shadow_rays = floor_and_sphere(matte(), point_light());
    let image = CpuRenderer::new(&no_shadow_rays).render(&RenderSettings { shadows: false, ..settings() });
    for (index, point, _) in floor_pixels(&no_shadow_rays, &image) {
        assert!(image.color[index].x > AMBIENT + 0.1, "floor at {point} is dark with shadows off");
    }
    let unlit = floor_and_sphere(matte(), vec![]);
    let image = CpuRenderer::new(&unlit).render(&settings());
    for (index, point, _) in floor_pixels(&unlit, &image) {
        assert!((image.color[index].x - AMBIENT).abs() < 1e-6, "unlit floor at {point} is not ambient only");
    }
}

#[test]
fn reflectivity_zero_equals_depth_one() {
    let scene = floor_and_sphere(matte(), point_light());
    let renderer = CpuRenderer::new(&scene);
    let two = renderer.render(&RenderSettings { max_depth: 2, ..settings() });
    let one = renderer.render(&RenderSettings { max_depth: 1, ..settings() });
    assert_eq!(two, one);
}

#[test]
fn a_reflective_floor_mirrors_the_sphere_and_the_background() {
    let mirror = Material { reflectivity: 0.5, ..matte() };
    let scene = floor_and_sphere(mirror, point_light());
    let renderer = CpuRenderer::new(&scene);
    let two = renderer.render(&RenderSettings { max_depth: 2, ..settings() });
    let one = renderer.render(&RenderSettings { max_depth: 1, ..settings() });
    let (mut mirrored_sphere, mut mirrored_sky) = (0, 0);
    for (index, point, ray) in floor_pixels(&scene, &two) {
        let reflected = Vec3::new(ray.direction.x, -ray.direction.y, ray.direction.z);
        let clearance = distance_to_line(SPHERE_CENTRE, point, reflected);
        let toward_sphere = (SPHERE_CENTRE - point).dot(reflected) > 0.0;
        // Half the floor's own shading plus half of what the mirror ray sees.
        let with_sky = 0.5 * one.color[index] + 0.5 * BACKGROUND;
        if toward_sphere && clearance < 0.8 * SPHERE_RADIUS {
            mirrored_sphere += 1;
            assert!((two.color[index] - with_sky).length() > 1e-2, "the sphere is not mirrored at {point}");
        } else if !toward_sphere || clearance > 1.3 * SPHERE_RADIUS {
            mirrored_sky += 1;
            assert!(
                (two.color[index] - with_sky).length() < 1e-5,
                "at {point}: {} vs {with_sky}",
                two.color[index]
            );
        }
    }
    assert!(mirrored_sphere > 20 && mirrored_sky > 1000, "sphere {mirrored_sphere}, sky {mirrored_sky}");
}

#[test]
fn ray_counts_follow_the_settings() {
    let pixels = u64::from(SIZE * SIZE);
    let matte_floor = CpuRenderer::new(&floor_and_sphere(matte(), point_light()));
    let (_, counts) = matte_floor.render_counting_rays(&settings());
    assert_eq!(counts.primary, pixels);
    assert_eq!(counts.reflection, 0, "nothing is reflective");
    assert!(counts.shadow > pixels / 2 && counts.shadow <= pixels, "one light: {counts:?}");
    let (_, unshadowed) = matte_floor.render_counting_rays(&RenderSettings { shadows: false, ..settings() });
    assert_eq!(unshadowed.shadow, 0);
    let mirror_floor =
        CpuRenderer::new(&floor_and_sphere(Material { reflectivity: 0.5, ..matte() }, point_light()));
    let (_, mirrored) = mirror_floor.render_counting_rays(&settings());
    assert!(mirrored.reflection > pixels / 4, "the floor covers much of the image: {mirrored:?}");
}
