//! The path integrator: unidirectional path tracing with next-event estimation, multiple
//! importance sampling (the power heuristic) between the BSDF and the lights, and Russian
//! roulette, over the kernels' BSDFs and lights.
//!
//! Random numbers come from the kernels' per-pixel sequence in a fixed layout (each bounce
//! owns `BOUNCE_DIMENSIONS` of them, whether it uses them or not), so that another backend
//! drawing from the same sequence follows the same path. `max_depth` counts path segments as
//! the Whitted integrator does (and Mitsuba's `max_depth`): 1 sees only what emits, 2 adds
//! direct light.
//!
//! Patches are thin two-sided surfaces: an opaque BSDF is shaded on the side the ray
//! arrives from; glass keeps its normal, which marks its outside. Every ray leaving a patch
//! starts off it along its normal by `path_ray_offset`, clear of its neighbours' surfaces,
//! and skips nothing beyond, so that no ray passes through a nearby wall into a closed shape.

use glam::Vec3;
use pointray_kernels::path_ray_offset;
use pointray_kernels::sampling::{to_local, to_world};
use pointray_kernels::{
    Bsdf, RandomSequence, Ray, bsdf_is_two_sided, bsdf_sample, face_forward, random_next, random_next2,
};
use pointray_scene::RenderSettings;

use crate::direct_light::{EmitterHit, SurfacePoint};
use crate::ray_counts::RayCounts;
use crate::renderer::CpuRenderer;
use crate::whitted::PrimaryAov;

/// The numbers each bounce draws: light choice (1), light position (2), BSDF lobe and
/// direction (3), Russian roulette (1).
pub const BOUNCE_DIMENSIONS: u32 = 7;
/// Paths shorter than this many segments are never cut by Russian roulette.
const ROULETTE_AFTER: u32 = 3;
/// The largest survival probability: even a white path ends some time.
const MAX_SURVIVAL: f32 = 0.95;

/// How the last bounce chose the direction now being followed: its density, for weighing
/// an emitter it meets against light sampling.
#[derive(Clone, Copy)]
pub(crate) struct Arrival {
    pub origin: Vec3,
    pub pdf: f32,
    /// From the camera or a delta lobe: light sampling could not have found the emitter.
    pub unweighted: bool,
}

impl CpuRenderer {
    /// One sample of the radiance along a camera ray, and the primary ray's AOVs with the
    /// albedo at the first hit.
    pub(crate) fn path_trace(
        &self,
        mut ray: Ray,
        mut random: RandomSequence,
        settings: &RenderSettings,
        counts: &mut RayCounts,
    ) -> (Vec3, PrimaryAov) {
        let mut radiance = Vec3::ZERO;
        let mut throughput = Vec3::ONE;
        let mut aov = PrimaryAov::MISS;
        let mut arrival = Arrival { origin: ray.origin, pdf: 0.0, unweighted: true };
        for depth in 0..settings.max_depth {
            random.dimension = depth * BOUNCE_DIMENSIONS;
            if depth == 0 {
                counts.primary += 1;
            } else {
                counts.reflection += 1;
            }
            let hit = self.closest_hit(&ray, 0.0, settings);
            let surface_t = hit.map_or(f32::INFINITY, |hit| hit.t);
            match self.emitter_on(&ray, surface_t) {
                EmitterHit::Surface => {}
                emitter => {
                    radiance += throughput * self.emitted(emitter, &ray, &arrival);
                    break;
                }
            }
            let Some(hit) = hit else { break };
            let surface = self.surface_point(&hit, &ray);
            if depth == 0 {
                aov = PrimaryAov {
                    depth: hit.t,
                    normal: face_forward(surface.normal, ray.direction),
                    instance_id: surface.object,
                    primitive_id: hit.primitive,
                    albedo: surface.bsdf.color,
                };
            }
            radiance += throughput * self.surface_emission(&surface, &ray, hit.t, &arrival);
            if depth + 1 >= settings.max_depth {
                break;
            }
            let normal = shading_normal(&surface.bsdf, surface.normal, ray.direction);
            let wo = to_local(-ray.direction, normal);
            radiance += throughput * self.direct_light(&surface, normal, wo, &mut random, settings, counts);
            let sample = bsdf_sample(&surface.bsdf, wo, {
                let u = random_next2(&mut random);
                Vec3::new(u.x, u.y, random_next(&mut random))
            });
            if sample.weight == Vec3::ZERO {
                break;
            }
            throughput *= sample.weight;
            let direction = to_world(sample.direction, normal);
            arrival = Arrival { origin: surface.position, pdf: sample.pdf, unweighted: sample.delta };
            ray = Ray::new(surface.leaving(direction, self.ray_epsilon), direction);
            if depth + 1 >= ROULETTE_AFTER {
                let survival = throughput.max_element().min(MAX_SURVIVAL);
                if random_next(&mut random) >= survival {
                    break;
                }
                throughput /= survival;
            }
        }
        (radiance, aov)
    }
}

/// The normal a BSDF is shaded with: turned toward the arriving ray for the two-sided
/// (opaque) kinds, as it is for glass, whose normal marks its outside.
fn shading_normal(bsdf: &Bsdf, normal: Vec3, ray_direction: Vec3) -> Vec3 {
    if bsdf_is_two_sided(bsdf) { face_forward(normal, ray_direction) } else { normal }
}

impl SurfacePoint {
    /// Where a ray leaving the surface along `direction` starts: off the surface by
    /// `path_ray_offset` on the side it leaves to, so that reflection and refraction alike
    /// start clear of the surface they leave and of its neighbours.
    pub(crate) fn leaving(&self, direction: Vec3, epsilon: f32) -> Vec3 {
        let side = if direction.dot(self.normal) >= 0.0 { 1.0 } else { -1.0 };
        self.position + self.normal * (side * path_ray_offset(self.clearance, epsilon))
    }
}
