//! Lights that a path samples directly (next-event estimation): point, directional, sphere
//! and quad lights, in one record so that both renderers (and a GPU buffer) hold them alike.
//! Twin of `shaders/light_source.glsl`. The sky is the background (`background.rs`).
//!
//! Units follow Mitsuba's: a point light's `radiance` is its intensity (falling off with the
//! squared distance), a directional light's its irradiance on a surface facing it, an area
//! light's the radiance it emits. A quad emits from the side its normal `edge_u × edge_v`
//! faces and is black behind, a sphere emits outward; both are opaque, as Mitsuba's area
//! lights are.

use glam::{Vec2, Vec3};

use crate::sampling::{to_world, uniform_cone, uniform_cone_pdf};

pub const LIGHT_POINT: u32 = 0;
pub const LIGHT_DIRECTIONAL: u32 = 1;
pub const LIGHT_SPHERE: u32 = 2;
pub const LIGHT_QUAD: u32 = 3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSource {
    pub kind: u32,
    /// A point light's position, a sphere's centre, a quad's corner.
    pub position: Vec3,
    /// A directional light's direction of travel; a quad's first edge.
    pub edge_u: Vec3,
    /// A quad's second edge.
    pub edge_v: Vec3,
    /// A sphere's radius.
    pub radius: f32,
    pub radiance: Vec3,
}

/// Light arriving at a point from one direction: `radiance` is what arrives (for the delta
/// lights, point and directional, the irradiance on a surface facing the light), `pdf` the
/// density per steradian with which the direction was drawn (0 for a delta light, and when
/// nothing arrives), `distance` how far the light is along `direction`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    pub direction: Vec3,
    pub distance: f32,
    pub radiance: Vec3,
    pub pdf: f32,
}

const NO_LIGHT: LightSample =
    LightSample { direction: Vec3::Z, distance: 0.0, radiance: Vec3::ZERO, pdf: 0.0 };

/// Whether the light is a point or a direction, which only light sampling reaches.
pub fn light_is_delta(light: &LightSource) -> bool {
    light.kind == LIGHT_POINT || light.kind == LIGHT_DIRECTIONAL
}

/// A direction toward the light from `position`, drawn from two uniform numbers.
pub fn light_sample(light: &LightSource, position: Vec3, u: Vec2) -> LightSample {
    match light.kind {
        LIGHT_POINT => {
            let offset = light.position - position;
            let distance2 = offset.length_squared();
            if distance2 <= 0.0 {
                return NO_LIGHT;
            }
            let distance = distance2.sqrt();
            LightSample {
                direction: offset / distance,
                distance,
                radiance: light.radiance / distance2,
                pdf: 0.0,
            }
        }
        LIGHT_DIRECTIONAL => LightSample {
            direction: -light.edge_u.normalize(),
            distance: f32::INFINITY,
            radiance: light.radiance,
            pdf: 0.0,
        },
        LIGHT_SPHERE => sphere_light_sample(light, position, u),
        _ => quad_light_sample(light, position, u),
    }
}

/// Uniform in the cone the sphere subtends.
fn sphere_light_sample(light: &LightSource, position: Vec3, u: Vec2) -> LightSample {
    let offset = light.position - position;
    let distance2 = offset.length_squared();
    let radius2 = light.radius * light.radius;
    if distance2 <= radius2 {
        return NO_LIGHT;
    }
    let cos_max = (1.0 - radius2 / distance2).max(0.0).sqrt();
    let direction = to_world(uniform_cone(u, cos_max), offset / distance2.sqrt());
    let distance = light_hit(light, position, direction);
    if !distance.is_finite() {
        return NO_LIGHT;
    }
    LightSample { direction, distance, radiance: light.radiance, pdf: uniform_cone_pdf(cos_max) }
}

/// Uniform over the quad's area, as a density per steradian.
fn quad_light_sample(light: &LightSource, position: Vec3, u: Vec2) -> LightSample {
    let point = light.position + u.x * light.edge_u + u.y * light.edge_v;
    let offset = point - position;
    let distance2 = offset.length_squared();
    if distance2 <= 0.0 {
        return NO_LIGHT;
    }
    let distance = distance2.sqrt();
    let direction = offset / distance;
    let pdf = light_pdf(light, position, direction, distance);
    if pdf <= 0.0 {
        return NO_LIGHT;
    }
    LightSample { direction, distance, radiance: light.radiance, pdf }
}

/// How far along the unit `direction` from `origin` an area light's surface is met (either
/// side of a quad); infinite where it is not (and always for the delta lights).
pub fn light_hit(light: &LightSource, origin: Vec3, direction: Vec3) -> f32 {
    match light.kind {
        LIGHT_SPHERE => {
            let offset = origin - light.position;
            let b = offset.dot(direction);
            let c = offset.length_squared() - light.radius * light.radius;
            let discriminant = b * b - c;
            if c <= 0.0 || discriminant < 0.0 {
                return f32::INFINITY;
            }
            let t = -b - discriminant.sqrt();
            if t > 0.0 { t } else { f32::INFINITY }
        }
        LIGHT_QUAD => {
            let normal = light.edge_u.cross(light.edge_v);
            let facing = direction.dot(normal);
            if facing == 0.0 {
                return f32::INFINITY;
            }
            let t = (light.position - origin).dot(normal) / facing;
            let local = origin + t * direction - light.position;
            let a = local.dot(light.edge_u) / light.edge_u.length_squared();
            let b = local.dot(light.edge_v) / light.edge_v.length_squared();
            if t > 0.0 && (0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b) { t } else { f32::INFINITY }
        }
        _ => f32::INFINITY,
    }
}

/// The radiance a ray travelling along `direction` receives from an area light it met: none
/// from behind a quad.
pub fn light_emitted(light: &LightSource, direction: Vec3) -> Vec3 {
    let behind = light.kind == LIGHT_QUAD && direction.dot(light.edge_u.cross(light.edge_v)) >= 0.0;
    if light_is_delta(light) || behind { Vec3::ZERO } else { light.radiance }
}

/// The density per steradian with which `light_sample` from `position` draws `direction`,
/// which meets the light at `distance`; 0 for the delta lights.
pub fn light_pdf(light: &LightSource, position: Vec3, direction: Vec3, distance: f32) -> f32 {
    match light.kind {
        LIGHT_SPHERE => {
            let distance2 = (light.position - position).length_squared();
            let radius2 = light.radius * light.radius;
            if distance2 <= radius2 {
                return 0.0;
            }
            uniform_cone_pdf((1.0 - radius2 / distance2).max(0.0).sqrt())
        }
        LIGHT_QUAD => {
            let normal = light.edge_u.cross(light.edge_v);
            let area = normal.length();
            let cos_light = -direction.dot(normal) / area;
            if cos_light <= 0.0 { 0.0 } else { distance * distance / (cos_light * area) }
        }
        _ => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use core::f32::consts::PI;

    use super::*;
    use crate::sampling::tests::halton;
    use crate::sampling::{UNIFORM_SPHERE_PDF, uniform_sphere};

    fn sphere() -> LightSource {
        LightSource {
            kind: LIGHT_SPHERE,
            position: Vec3::new(0.0, 0.0, 3.0),
            edge_u: Vec3::ZERO,
            edge_v: Vec3::ZERO,
            radius: 1.0,
            radiance: Vec3::ONE,
        }
    }

    fn quad() -> LightSource {
        // 1 x 2 at height 2, facing down.
        LightSource {
            kind: LIGHT_QUAD,
            position: Vec3::new(-0.5, -1.0, 2.0),
            edge_u: Vec3::new(0.0, 2.0, 0.0),
            edge_v: Vec3::new(1.0, 0.0, 0.0),
            radius: 0.0,
            radiance: Vec3::splat(3.0),
        }
    }

    /// Irradiance on an upward surface at the origin, by light sampling and by directions
    /// uniform on the sphere that meet the light; the two must agree.
    fn irradiance_both_ways(light: &LightSource) -> (f32, f32) {
        let count = 200_000;
        let by_light: f32 = (0..count)
            .map(|i| {
                let s = light_sample(light, Vec3::ZERO, halton(i));
                if s.pdf > 0.0 { s.radiance.x * s.direction.z.max(0.0) / s.pdf } else { 0.0 }
            })
            .sum::<f32>()
            / count as f32;
        let by_sphere: f32 = (0..count)
            .map(|i| {
                let d = uniform_sphere(halton(i));
                if light_hit(light, Vec3::ZERO, d).is_finite() {
                    light_emitted(light, d).x * d.z.max(0.0) / UNIFORM_SPHERE_PDF
                } else {
                    0.0
                }
            })
            .sum::<f32>()
            / count as f32;
        (by_light, by_sphere)
    }

    #[test]
    fn a_sphere_light_gives_its_analytic_irradiance() {
        // A sphere of radius r at distance d straight above: E = π L (r / d)².
        let (by_light, by_sphere) = irradiance_both_ways(&sphere());
        let expected = PI / 9.0;
        assert!((by_light - expected).abs() < 2e-3 * expected, "{by_light} against {expected}");
        assert!((by_sphere - expected).abs() < 0.02 * expected, "{by_sphere} against {expected}");
    }

    #[test]
    fn quad_light_sampling_agrees_with_hitting_it() {
        let (by_light, by_sphere) = irradiance_both_ways(&quad());
        assert!((by_light - by_sphere).abs() < 0.02 * by_light, "{by_light} against {by_sphere}");
    }

    #[test]
    fn area_light_densities_integrate_to_one() {
        for light in [sphere(), quad()] {
            let count = 400_000;
            let total: f32 = (0..count)
                .map(|i| {
                    let d = uniform_sphere(halton(i));
                    let t = light_hit(&light, Vec3::ZERO, d);
                    if t.is_finite() { light_pdf(&light, Vec3::ZERO, d, t) / UNIFORM_SPHERE_PDF } else { 0.0 }
                })
                .sum::<f32>()
                / count as f32;
            assert!((total - 1.0).abs() < 0.02, "{light:?}: {total}");
        }
    }

    #[test]
    fn a_quad_is_dark_and_opaque_from_behind_and_a_point_light_falls_off() {
        let above = Vec3::new(0.0, 0.0, 5.0);
        assert_eq!(light_sample(&quad(), above, Vec2::splat(0.5)).radiance, Vec3::ZERO);
        assert_eq!(light_hit(&quad(), above, Vec3::NEG_Z), 3.0, "the quad stops rays from behind");
        assert_eq!(light_emitted(&quad(), Vec3::NEG_Z), Vec3::ZERO);
        assert_eq!(light_emitted(&quad(), Vec3::Z), Vec3::splat(3.0));
        let point = LightSource { kind: LIGHT_POINT, position: Vec3::new(0.0, 0.0, 2.0), ..quad() };
        let s = light_sample(&point, Vec3::ZERO, Vec2::ZERO);
        assert!(light_is_delta(&point) && s.pdf == 0.0);
        assert!((s.radiance.x - 0.75).abs() < 1e-6 && s.direction == Vec3::Z && s.distance == 2.0);
    }
}
