//! The Whitted integrator: one camera ray's path, primary hit, then mirror bounces,
//! iteratively (the rendering contract: up to `max_depth` segments, each hit's Phong weighted
//! by `1 - reflectivity` when the path goes on). The path integrator is `path_tracer`.

use glam::Vec3;
use pointray_kernels::interpolate_color::color_from_rgba8;
use pointray_kernels::{Ray, face_forward, interpolate_color, patch_normal, self_clearance};
use pointray_scene::{Geometry, RenderSettings, RenderedImage};

use crate::object_bvh::triangle_corners;
use crate::ray_counts::RayCounts;
use crate::renderer::CpuRenderer;
use crate::shading::ShadingPoint;
use crate::top_level::SceneHit;

/// The AOVs of a primary ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimaryAov {
    pub depth: f32,
    pub normal: Vec3,
    pub instance_id: u32,
    pub primitive_id: u32,
    /// The BSDF's colour at the hit (path integrator only; zero under Whitted).
    pub albedo: Vec3,
}

impl PrimaryAov {
    pub const MISS: Self = Self {
        depth: f32::INFINITY,
        normal: Vec3::ZERO,
        instance_id: RenderedImage::MISS,
        primitive_id: RenderedImage::MISS,
        albedo: Vec3::ZERO,
    };
}

impl CpuRenderer {
    /// The radiance along `ray`, and the AOVs of its first segment.
    pub(crate) fn trace_whitted(
        &self,
        mut ray: Ray,
        settings: &RenderSettings,
        counts: &mut RayCounts,
    ) -> (Vec3, PrimaryAov) {
        let mut radiance = Vec3::ZERO;
        let mut weight = 1.0;
        let mut aov = PrimaryAov::MISS;
        let mut t_min = 0.0;
        for depth in 0..settings.max_depth {
            if depth == 0 {
                counts.primary += 1;
            } else {
                counts.reflection += 1;
            }
            let Some(hit) = self.closest_hit(&ray, t_min, settings) else {
                return (radiance + weight * self.background(ray.direction), aov);
            };
            let instance = &self.top.instances[hit.instance];
            let object = &self.scene.objects[instance.object_index as usize];
            let normal = face_forward(instance.normal_to_world(self.object_normal(&hit)), ray.direction);
            let position = ray.at(hit.t);
            if depth == 0 {
                aov = PrimaryAov {
                    depth: hit.t,
                    normal,
                    instance_id: instance.object_index,
                    primitive_id: hit.primitive,
                    albedo: Vec3::ZERO,
                };
            }
            let point = ShadingPoint {
                position,
                normal,
                to_viewer: -ray.direction,
                base_color: self.base_color(&hit, &ray),
                clearance: self.clearance(&hit),
            };
            let local = self.shade(&point, &object.material, settings, counts);
            let reflectivity = object.material.reflectivity;
            if reflectivity <= 0.0 || depth + 1 >= settings.max_depth {
                return (radiance + weight * local, aov);
            }
            radiance += weight * (1.0 - reflectivity) * local;
            weight *= reflectivity;
            let mirrored = ray.direction - 2.0 * normal.dot(ray.direction) * normal;
            ray = Ray::new(position + normal * self.ray_epsilon, mirrored);
            t_min = point.clearance;
        }
        (radiance, aov)
    }

    /// The hit primitive's normal in object space (not face-forwarded, any length).
    pub(crate) fn object_normal(&self, hit: &SceneHit) -> Vec3 {
        let index = hit.primitive as usize;
        match self.top.instances[hit.instance].blas.geometry() {
            Geometry::Patches(patches) => patch_normal(&patches.hot[index].decode(), hit.uv),
            Geometry::Mesh(mesh) => {
                let [a, b, c] = triangle_corners(mesh, index);
                (b - a).cross(c - a)
            }
        }
    }

    /// How far secondary rays leaving the hit ignore what they meet: a fraction of the hit
    /// patch's support radius in world units, nothing for triangles.
    pub(crate) fn clearance(&self, hit: &SceneHit) -> f32 {
        let instance = &self.top.instances[hit.instance];
        match instance.blas.geometry() {
            Geometry::Patches(patches) => {
                self_clearance(patches.hot[hit.primitive as usize].radius() * instance.world_scale())
            }
            Geometry::Mesh(_) => 0.0,
        }
    }

    /// The material's diffuse colour, or where the material asks for point colours, the
    /// point colours interpolated at the hit (white for meshes, which have none).
    pub(crate) fn base_color(&self, hit: &SceneHit, ray: &Ray) -> Vec3 {
        let instance = &self.top.instances[hit.instance];
        let material = &self.scene.objects[instance.object_index as usize].material;
        if !material.use_point_colors {
            return material.diffuse;
        }
        match instance.blas.geometry() {
            Geometry::Patches(patches) => {
                // In object space, where the patches are; `t` is the same there.
                let position = instance.to_object(ray).at(hit.t);
                let (hot, cold, neighbors) = (&patches.hot, &patches.cold, &patches.color_neighbors);
                color_from_rgba8(interpolate_color(position, hit.primitive, hot, cold, neighbors))
            }
            Geometry::Mesh(_) => Vec3::ONE,
        }
    }

    pub(crate) fn background(&self, direction: Vec3) -> Vec3 {
        self.scene.background.radiance(direction)
    }
}
