//! Small scenes built in code for the Vulkan renderer's tests (a sphere or a model on a
//! floor), and measures of the images drawn.

use std::sync::Arc;

use glam::{Affine3A, UVec2, Vec3};
use pointray_io::TriangleMesh;
use pointray_kernels::{Aabb, PatchCold, PatchHot, camera_ray};
use pointray_patches::PatchSet;
use pointray_scene::{
    Background, Camera, Geometry, Light, Material, RenderSettings, RenderedImage, Scene, SceneObject,
};

pub fn settings(size: u32) -> RenderSettings {
    RenderSettings { width: size, height: size, ..RenderSettings::default() }
}

/// A square floor of two triangles at height `y`, `half` wide each way, facing up.
pub fn floor(y: f32, half: f32) -> TriangleMesh {
    let corner = |x: f32, z: f32| Vec3::new(x * half, y, z * half);
    TriangleMesh {
        positions: vec![corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)],
        triangles: vec![[0, 2, 1], [0, 3, 2]],
    }
}

/// Points on a sphere (a Fibonacci spiral), each as the sphere's osculating quadratic patch:
/// `w = -(u² + v²) / (2 r)` over its tangent plane, reaching `spacing_factor` spacings out.
pub fn sphere_patches(center: Vec3, radius: f32, count: usize) -> PatchSet {
    let spacing = radius * (4.0 * std::f32::consts::PI / count as f32).sqrt();
    let support = 1.5 * spacing;
    let curvature = -0.5 / radius;
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let mut set = PatchSet::default();
    for i in 0..count {
        let y = 1.0 - 2.0 * (i as f32 + 0.5) / count as f32;
        let ring = (1.0 - y * y).sqrt();
        let angle = golden * i as f32;
        let normal = Vec3::new(ring * angle.cos(), y, ring * angle.sin());
        let origin = center + radius * normal;
        let coefficients = [0.0, 0.0, 0.0, curvature, 0.0, curvature];
        set.hot.to_mut().push(PatchHot::isotropic(
            origin,
            normal.any_orthonormal_vector(),
            normal,
            coefficients,
            support,
        ));
        set.cold.to_mut().push(PatchCold::default());
        set.aabbs.to_mut().push(Aabb::cube(origin, support));
    }
    set
}

pub fn object(name: &str, geometry: Geometry, material: Material) -> SceneObject {
    SceneObject { name: name.into(), transform: Affine3A::IDENTITY, material, geometry }
}

pub fn patches(set: PatchSet) -> Geometry {
    Geometry::Patches(Arc::new(set))
}

pub fn mesh(mesh: TriangleMesh) -> Geometry {
    Geometry::Mesh(Arc::new(mesh))
}

pub fn point_light(position: Vec3, intensity: f32) -> Light {
    Light::point(position, Vec3::ONE, intensity)
}

/// A unit sphere at (0, 1, 0) on a floor at y = 0, lit from above and to the side.
pub fn sphere_on_floor(floor_reflectivity: f32, light_intensity: f32) -> Scene {
    let floor_material = Material { reflectivity: floor_reflectivity, ..Material::default() };
    let sphere_material = Material { diffuse: Vec3::new(0.8, 0.3, 0.2), ..Material::default() };
    Scene {
        camera: Camera {
            position: Vec3::new(0.0, 2.5, 5.0),
            look_at: Vec3::new(0.0, 0.7, 0.0),
            up: Vec3::Y,
            vertical_fov_degrees: 45.0,
        },
        lights: vec![point_light(Vec3::new(2.0, 6.0, 1.0), light_intensity)],
        background: Background::Gradient { top: Vec3::new(0.5, 0.7, 1.0), bottom: Vec3::ONE },
        objects: vec![
            object("sphere", patches(sphere_patches(Vec3::Y, 1.0, 6000)), sphere_material),
            object("floor", mesh(floor(0.0, 4.0)), floor_material),
        ],
    }
}

/// The world-space ray of pixel `index`'s first sample, as the renderer shot it.
pub fn primary_ray(camera: &Camera, image: &RenderedImage, index: usize) -> pointray_kernels::Ray {
    let pixel = UVec2::new(index as u32 % image.width, index as u32 / image.width);
    camera_ray(camera, UVec2::new(image.width, image.height), pixel, pointray_kernels::sample_jitter(0))
}

/// Intersection over union of two hit masks.
pub fn iou(a: &[bool], b: &[bool]) -> f64 {
    let both = a.iter().zip(b).filter(|(x, y)| **x && **y).count();
    let either = a.iter().zip(b).filter(|(x, y)| **x || **y).count();
    if either == 0 { 1.0 } else { both as f64 / either as f64 }
}

/// Mean of the colour's channels over the selected pixels.
pub fn mean_luminance(image: &RenderedImage, select: impl Fn(usize) -> bool) -> f32 {
    let (sum, count) = (0..image.pixel_count())
        .filter(|&i| select(i))
        .fold((0.0, 0usize), |(sum, count), i| (sum + image.color[i].element_sum() / 3.0, count + 1));
    sum / count.max(1) as f32
}

/// `model` (object 0) on a floor just under `bounds`, lit from above, framed from the front
/// and a little above: the paper's figure setting.
pub fn model_on_floor(model: SceneObject, bounds: Aabb, floor_reflectivity: f32) -> Scene {
    let size = (Vec3::from(bounds.max) - Vec3::from(bounds.min)).max_element();
    let floor_material = Material { reflectivity: floor_reflectivity, ..Material::default() };
    Scene {
        camera: Scene::framing_camera(&bounds, Vec3::new(0.3, 0.4, 1.0), 40.0, 1.0),
        lights: vec![point_light(Vec3::from(bounds.max) + Vec3::splat(size), 1.0)],
        background: Background::Solid(Vec3::splat(0.2)),
        objects: vec![model, object("floor", mesh(floor(bounds.min[1], 4.0 * size)), floor_material)],
    }
}
