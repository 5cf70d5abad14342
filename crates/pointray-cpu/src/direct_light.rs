//! Light reaching a path's vertex: next-event estimation (one light, or the sky, drawn per
//! vertex and weighed against the BSDF by the power heuristic), and what a path meets when
//! its ray finds an area light or the sky instead of a surface.
//!
//! The lights chosen from are the scene's lights, the sky (the background) when it is not
//! black, and the emissive mesh triangles when there are any, each with probability
//! `1 / count`; the sky is drawn as `Background::sample` draws it (a map in proportion to its
//! radiance), the triangles by area (`emissive_sample`). Area lights are not in the BVHs: a
//! path's ray and a shadow ray test them apart; emissive triangles are, and a path that
//! meets one weighs its emission against light sampling too.

use glam::Vec3;
use pointray_kernels::sampling::{power_heuristic, to_local};
use pointray_kernels::{
    Bsdf, LightSample, LightSource, RandomSequence, Ray, bsdf_eval, bsdf_pdf, bsdf_samples_lights,
    emissive_pdf, emissive_sample, light_emitted, light_hit, light_is_delta, light_pdf, light_sample,
    random_next, random_next2,
};
use pointray_scene::RenderSettings;

use crate::path_tracer::Arrival;
use crate::ray_counts::RayCounts;
use crate::renderer::CpuRenderer;
use crate::top_level::SceneHit;

/// A surface hit ready for the path integrator, in world space.
pub(crate) struct SurfacePoint {
    pub position: Vec3,
    /// The surface's own normal (a patch's, or a triangle's by its winding), unit length.
    pub normal: Vec3,
    pub bsdf: Bsdf,
    pub emission: Vec3,
    /// The hit patch's `self_clearance`, which sets how far rays leaving it start off it
    /// (`path_ray_offset`); zero for triangles.
    pub clearance: f32,
    pub object: u32,
}

/// What a path's ray meets first.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum EmitterHit {
    /// A surface before any area light.
    Surface,
    /// The area light of this index, at this distance.
    Light(usize, f32),
    /// Nothing: the sky (the background), black or not.
    Sky,
}

impl CpuRenderer {
    pub(crate) fn surface_point(&self, hit: &SceneHit, ray: &Ray) -> SurfacePoint {
        let instance = &self.top.instances[hit.instance];
        let material = &self.scene.objects[instance.object_index as usize].material;
        SurfacePoint {
            position: ray.at(hit.t),
            normal: instance.normal_to_world(self.object_normal(hit)),
            bsdf: material.bsdf(self.base_color(hit, ray)),
            emission: material.emission,
            clearance: self.clearance(hit),
            object: instance.object_index,
        }
    }

    /// How many things light sampling chooses from: the lights, the sky unless black, and
    /// the emissive triangles if any.
    fn emitter_count(&self) -> usize {
        self.scene.lights.len()
            + usize::from(self.scene.background.is_lit())
            + usize::from(!self.emissive.is_empty())
    }

    /// The emission a path's ray meets on `surface`, `t` along it, weighed against light
    /// sampling where the surface is an emissive triangle that it could have drawn.
    pub(crate) fn surface_emission(
        &self,
        surface: &SurfacePoint,
        ray: &Ray,
        t: f32,
        arrival: &Arrival,
    ) -> Vec3 {
        let is_triangle = surface.clearance == 0.0;
        if surface.emission == Vec3::ZERO || !is_triangle || arrival.unweighted || self.emissive.is_empty() {
            return surface.emission;
        }
        let choice = 1.0 / self.emitter_count() as f32;
        let light_density = emissive_pdf(&self.emissive, t, surface.normal.dot(ray.direction));
        surface.emission * power_heuristic(arrival.pdf, choice * light_density)
    }

    /// The nearest area light on `ray` before `surface_t`; else the sky if the ray hit
    /// nothing; else the surface.
    pub(crate) fn emitter_on(&self, ray: &Ray, surface_t: f32) -> EmitterHit {
        let mut nearest = EmitterHit::Surface;
        let mut nearest_t = surface_t;
        for (index, light) in self.scene.lights.iter().enumerate() {
            let t = light_hit(&light.source(), ray.origin, ray.direction);
            if t < nearest_t {
                (nearest, nearest_t) = (EmitterHit::Light(index, t), t);
            }
        }
        if nearest == EmitterHit::Surface && !surface_t.is_finite() {
            return EmitterHit::Sky;
        }
        nearest
    }

    /// The radiance a path's ray receives from the emitter it met, weighed against light
    /// sampling, which could have found it from the last vertex.
    pub(crate) fn emitted(&self, emitter: EmitterHit, ray: &Ray, arrival: &Arrival) -> Vec3 {
        let choice = 1.0 / self.emitter_count().max(1) as f32;
        let (radiance, light_density) = match emitter {
            EmitterHit::Surface => return Vec3::ZERO,
            EmitterHit::Sky => (self.background(ray.direction), self.scene.background.pdf(ray.direction)),
            EmitterHit::Light(index, t) => {
                let light = self.scene.lights[index].source();
                (light_emitted(&light, ray.direction), light_pdf(&light, arrival.origin, ray.direction, t))
            }
        };
        if arrival.unweighted {
            return radiance;
        }
        radiance * power_heuristic(arrival.pdf, choice * light_density)
    }

    /// Next-event estimation at `surface`, shaded with `normal` and seen from local `wo`.
    pub(crate) fn direct_light(
        &self,
        surface: &SurfacePoint,
        normal: Vec3,
        wo: Vec3,
        random: &mut RandomSequence,
        settings: &RenderSettings,
        counts: &mut RayCounts,
    ) -> Vec3 {
        let pick = random_next(random);
        let u = random_next2(random);
        let count = self.emitter_count();
        if count == 0 || !bsdf_samples_lights(&surface.bsdf) {
            return Vec3::ZERO;
        }
        let index = ((pick * count as f32) as usize).min(count - 1);
        let lights = self.scene.lights.len();
        let (arriving, delta) = match self.scene.lights.get(index) {
            Some(light) => {
                let source = light.source();
                (light_sample(&source, surface.position, u), light_is_delta(&source))
            }
            None if index == lights && self.scene.background.is_lit() => {
                (self.scene.background.sample(u), false)
            }
            None => {
                // What is left of `pick` within the triangles' share picks the triangle.
                let within = (pick * count as f32 - index as f32).clamp(0.0, 1.0);
                (emissive_sample(&self.emissive, within, u, surface.position), false)
            }
        };
        if arriving.radiance == Vec3::ZERO || (!delta && arriving.pdf <= 0.0) {
            return Vec3::ZERO;
        }
        let wi = to_local(arriving.direction, normal);
        let reflected = bsdf_eval(&surface.bsdf, wo, wi);
        if reflected == Vec3::ZERO {
            return Vec3::ZERO;
        }
        counts.shadow += 1;
        if self.blocked(surface, &arriving, index, settings) {
            return Vec3::ZERO;
        }
        let choice = 1.0 / count as f32;
        if delta {
            return reflected * arriving.radiance / choice;
        }
        let weight = power_heuristic(choice * arriving.pdf, bsdf_pdf(&surface.bsdf, wo, wi));
        reflected * arriving.radiance * (weight / (choice * arriving.pdf))
    }

    /// Whether a surface or another area light lies between `surface` and the light sample.
    fn blocked(
        &self,
        surface: &SurfacePoint,
        arriving: &LightSample,
        light: usize,
        settings: &RenderSettings,
    ) -> bool {
        let origin = surface.leaving(arriving.direction, self.ray_epsilon);
        // Aimed from the ray's origin, off the surface, at the point sampled on the light, and
        // stopping short of it (an emissive triangle's own surface is in the BVHs).
        let (direction, distance) = if arriving.distance.is_finite() {
            let to_light = surface.position + arriving.direction * arriving.distance - origin;
            let length = to_light.length();
            (to_light / length, length * (1.0 - 1e-4))
        } else {
            (arriving.direction, f32::INFINITY)
        };
        let others = self.scene.lights.iter().enumerate().filter(|&(index, _)| index != light);
        let in_the_way = |source: LightSource| light_hit(&source, origin, direction) < distance;
        others.map(|(_, other)| other.source()).any(in_the_way)
            || self.occluded(&Ray::new(origin, direction), 0.0, distance, settings)
    }
}
