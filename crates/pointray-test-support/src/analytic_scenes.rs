//! Hand-built scenes for the CPU renderer's tests: analytic patches, so that each test knows
//! exactly where the surface is.

use std::sync::Arc;

use glam::{Affine3A, Vec3};
use pointray_io::TriangleMesh;
use pointray_kernels::{Aabb, PatchCold, PatchHot};
use pointray_patches::PatchSet;
use pointray_scene::{
    Background, Camera, Geometry, Integrator, Light, Material, RenderSettings, Scene, SceneObject,
};

pub const BACKGROUND: Vec3 = Vec3::new(0.1, 0.2, 0.3);

/// Builds a patch set from patches, each boxed by its own cube (the paper's box).
pub fn patch_set(hot: Vec<PatchHot>) -> PatchSet {
    PatchSet {
        aabbs: hot.iter().map(|p| Aabb::cube(p.origin(), p.radius())).collect(),
        cold: vec![PatchCold::default(); hot.len()].into(),
        hot: hot.into(),
        ..PatchSet::default()
    }
}

/// Flat patches on the plane y = 0 over `[-half, half]²`, `count` a side, each with a
/// support radius of one grid spacing (as a 9-neighbour fit would give).
pub fn plane_patches(half: f32, count: u32) -> PatchSet {
    let spacing = 2.0 * half / (count - 1) as f32;
    let hot = (0..count * count)
        .map(|i| {
            let (ix, iz) = (i % count, i / count);
            let origin = Vec3::new(-half + ix as f32 * spacing, 0.0, -half + iz as f32 * spacing);
            PatchHot::isotropic(origin, Vec3::X, Vec3::Y, [0.0; 6], spacing)
        })
        .collect();
    patch_set(hot)
}

/// Patches of a sphere at the origin: `count` Fibonacci points, each patch the sphere's
/// osculating paraboloid `w = -(u² + v²) / 2r` with a support radius of twice the spacing.
pub fn sphere_patches(radius: f32, count: u32) -> PatchSet {
    let spacing = radius * (4.0 * std::f32::consts::PI / count as f32).sqrt();
    let curvature = -0.5 / radius;
    let hot = (0..count)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / count as f32;
            let ring = (1.0 - y * y).max(0.0).sqrt();
            let azimuth = std::f32::consts::TAU * (i as f32 * 0.618_034).fract();
            let normal = Vec3::new(ring * azimuth.cos(), y, ring * azimuth.sin());
            let tangent = normal.any_orthonormal_vector();
            PatchHot::isotropic(
                normal * radius,
                tangent,
                normal,
                [0.0, 0.0, 0.0, curvature, 0.0, curvature],
                2.0 * spacing,
            )
        })
        .collect();
    patch_set(hot)
}

/// A square of two triangles on y = 0 over `[-half, half]²`.
pub fn floor_mesh(half: f32) -> TriangleMesh {
    TriangleMesh {
        positions: vec![
            Vec3::new(-half, 0.0, -half),
            Vec3::new(half, 0.0, -half),
            Vec3::new(half, 0.0, half),
            Vec3::new(-half, 0.0, half),
        ],
        triangles: vec![[0, 2, 1], [0, 3, 2]],
    }
}

pub fn patches_object(name: &str, patches: PatchSet, transform: Affine3A, material: Material) -> SceneObject {
    SceneObject { name: name.into(), transform, material, geometry: Geometry::Patches(Arc::new(patches)) }
}

pub fn mesh_object(name: &str, mesh: TriangleMesh, material: Material) -> SceneObject {
    SceneObject {
        name: name.into(),
        transform: Affine3A::IDENTITY,
        material,
        geometry: Geometry::Mesh(Arc::new(mesh)),
    }
}

/// A matte material: ambient 0.1, no specular, no reflection.
pub fn matte() -> Material {
    Material { ambient: 0.1, diffuse: Vec3::splat(0.8), specular: 0.0, shininess: 1.0, ..Material::default() }
}

pub fn scene(camera: Camera, lights: Vec<Light>, objects: Vec<SceneObject>) -> Scene {
    Scene { camera, lights, background: Background::Solid(BACKGROUND), objects }
}

pub fn camera(position: Vec3, look_at: Vec3) -> Camera {
    Camera { position, look_at, up: Vec3::Y, vertical_fov_degrees: 40.0 }
}

/// The world ray through pixel `(x, y)`'s centre, as the renderer casts it.
pub fn pixel_ray(camera: &Camera, width: u32, height: u32, x: u32, y: u32) -> pointray_kernels::Ray {
    pointray_kernels::camera_ray(
        camera,
        glam::UVec2::new(width, height),
        glam::UVec2::new(x, y),
        pointray_kernels::sample_jitter(0),
    )
}

/// Square path-traced renders of `size` pixels, `spp` samples a pixel and paths of up to
/// `max_depth` segments, from `seed`.
pub fn path_settings(size: u32, spp: u32, max_depth: u32, seed: u32) -> RenderSettings {
    RenderSettings {
        width: size,
        height: size,
        samples_per_pixel: spp,
        max_depth,
        integrator: Integrator::Path,
        seed,
        ..RenderSettings::default()
    }
}
