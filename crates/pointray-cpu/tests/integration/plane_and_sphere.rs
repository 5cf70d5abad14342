//! Geometry from primary rays: a point-set plane has no holes; a sampled sphere's normals
//! and depths match the analytic sphere.

use crate::common;

use common::*;
use glam::{Affine3A, Quat, Vec3};
use pointray_cpu::{CpuRenderer, render};
use pointray_scene::{PatchAcceptance, RenderSettings, RenderedImage};

fn settings(width: u32, height: u32) -> RenderSettings {
    RenderSettings { width, height, ..RenderSettings::default() }
}

#[test]
fn a_point_set_plane_renders_without_holes() {
    let half = 1.0;
    let camera = camera(Vec3::new(0.3, 2.5, 2.0), Vec3::ZERO);
    let plane = patches_object("plane", plane_patches(half, 41), Affine3A::IDENTITY, matte());
    let scene = scene(camera, vec![], vec![plane]);
    let (width, height) = (96, 80);
    for acceptance in [PatchAcceptance::Box, PatchAcceptance::Disk] {
        let image = render(&scene, &RenderSettings { acceptance, ..settings(width, height) });
        let mut inside = 0;
        for y in 0..height {
            for x in 0..width {
                // Where the pixel's ray meets y = 0, analytically.
                let ray = pixel_ray(&scene.camera, width, height, x, y);
                let t = -ray.origin.y / ray.direction.y;
                let on_plane = ray.at(t);
                let index = (y * width + x) as usize;
                if t > 0.0 && on_plane.x.abs() < 0.95 * half && on_plane.z.abs() < 0.95 * half {
                    inside += 1;
                    assert_eq!(image.instance_id[index], 0, "hole at pixel ({x}, {y}) with {acceptance:?}");
                    assert!((image.depth[index] - t).abs() < 1e-3 * t, "depth at ({x}, {y})");
                    assert!((image.normal[index] - Vec3::Y).length() < 1e-5);
                }
                if t <= 0.0 || on_plane.x.abs() > 1.5 * half || on_plane.z.abs() > 1.5 * half {
                    assert_eq!(image.instance_id[index], RenderedImage::MISS, "false surface at ({x}, {y})");
                    assert_eq!(image.color[index], BACKGROUND);
                }
            }
        }
        assert!(inside > width * height / 4, "the plane should fill much of the image, got {inside} pixels");
    }
}

#[test]
fn sphere_normals_and_depths_match_the_analytic_sphere() {
    // A sphere of radius 0.5 in object space, scaled by 2, turned and moved: world radius 1.
    let centre = Vec3::new(0.5, -0.2, 0.3);
    let transform =
        Affine3A::from_scale_rotation_translation(Vec3::splat(2.0), Quat::from_rotation_y(0.7), centre);
    let sphere = patches_object("sphere", sphere_patches(0.5, 4000), transform, matte());
    let scene = scene(camera(Vec3::new(0.5, 1.0, 5.0), centre), vec![], vec![sphere]);
    let (width, height) = (96, 96);
    let image = CpuRenderer::new(&scene).render(&settings(width, height));
    let mut angles = Vec::new();
    for y in 0..height {
        for x in 0..width {
            let index = (y * width + x) as usize;
            let ray = pixel_ray(&scene.camera, width, height, x, y);
            let Some(t) = ray_sphere(ray.origin - centre, ray.direction, 1.0) else { continue };
            // Skip the silhouette, where the patches' cubes and the true sphere may disagree.
            if (ray.at(t) - centre).normalize().dot(-ray.direction) < 0.2 {
                continue;
            }
            assert_eq!(image.instance_id[index], 0, "missed the sphere at ({x}, {y})");
            assert!(
                (image.depth[index] - t).abs() < 0.01,
                "depth {} vs {t} at ({x}, {y})",
                image.depth[index]
            );
            let truth = (ray.at(image.depth[index]) - centre).normalize();
            angles.push(image.normal[index].angle_between(truth).to_degrees());
        }
    }
    assert!(angles.len() > 1000, "too few sphere pixels: {}", angles.len());
    let mean = angles.iter().sum::<f32>() / angles.len() as f32;
    assert!(mean < 2.0, "mean normal error {mean} degrees");
}

#[test]
fn samples_average_and_aovs_come_from_the_first_sample() {
    let plane = patches_object("plane", plane_patches(1.0, 21), Affine3A::IDENTITY, matte());
    let lights = vec![pointray_scene::Light::Directional {
        direction: Vec3::new(0.2, -1.0, -0.3),
        color: Vec3::ONE,
        intensity: 1.0,
    }];
    let scene = scene(camera(Vec3::new(0.0, 2.0, 2.0), Vec3::ZERO), lights, vec![plane]);
    let renderer = CpuRenderer::new(&scene);
    let one = renderer.render(&settings(32, 24));
    let four = renderer.render(&RenderSettings { samples_per_pixel: 4, ..settings(32, 24) });
    assert_eq!(one.depth, four.depth);
    assert_eq!(one.instance_id, four.instance_id);
    assert_eq!(one.primitive_id, four.primitive_id);
    // Jittered samples straddle the plane's edge: some edge pixels blend plane and background.
    let blended = one.color.iter().zip(&four.color).filter(|(a, b)| (**a - **b).length() > 1e-3).count();
    assert!(blended > 0, "supersampling changed nothing");
    let hit_ids = one.primitive_id.iter().filter(|&&id| id != RenderedImage::MISS);
    assert!(hit_ids.clone().all(|&id| id < 21 * 21));
}

/// The nearest positive `t` of `origin + t dir` (unit dir) on the sphere of `radius` at 0.
fn ray_sphere(origin: Vec3, direction: Vec3, radius: f32) -> Option<f32> {
    let b = origin.dot(direction);
    let disc = b * b - (origin.length_squared() - radius * radius);
    let t = -b - disc.sqrt();
    (disc >= 0.0 && t > 0.0).then_some(t)
}
