//! The surface a path meets: one record for every kind of BSDF, so that both renderers
//! (and a GPU buffer) hold it alike, and the dispatch to each kind. Twin of
//! `shaders/bsdf.glsl`.
//!
//! Local directions, the shading normal along +z. The opaque kinds are two-sided: the
//! caller turns the normal toward the arriving ray (`bsdf_is_two_sided`). Glass keeps its
//! normal, which marks its outside. Emission is the material's, not the BSDF's.

use glam::{Vec3, Vec3Swizzles};

use crate::bsdf_sample::BsdfSample;
use crate::dielectric::dielectric_sample;
use crate::lambert::{lambert_eval, lambert_pdf, lambert_sample};
use crate::microfacet::MIN_ALPHA;
use crate::rough_conductor::{rough_conductor_eval, rough_conductor_pdf, rough_conductor_sample};
use crate::rough_plastic::{rough_plastic_eval, rough_plastic_pdf, rough_plastic_sample};

/// Lambert, `color` the albedo.
pub const BSDF_DIFFUSE: u32 = 0;
/// A rough metal, `color` its reflectance head on.
pub const BSDF_CONDUCTOR: u32 = 1;
/// A rough plastic, `color` its base's albedo, `ior` its coating's index.
pub const BSDF_PLASTIC: u32 = 2;
/// Glass, smooth when `roughness` is 0; `color` tints the transmission.
pub const BSDF_DIELECTRIC: u32 = 3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bsdf {
    pub kind: u32,
    pub color: Vec3,
    /// GGX α (Mitsuba's `alpha`); below `MIN_ALPHA` it is `MIN_ALPHA`, except that glass of
    /// roughness 0 is smooth.
    pub roughness: f32,
    pub ior: f32,
}

/// Whether the BSDF treats both sides alike (the caller face-forwards the normal).
pub fn bsdf_is_two_sided(bsdf: &Bsdf) -> bool {
    bsdf.kind != BSDF_DIELECTRIC
}

/// Whether light sampling can be weighed against this BSDF (it can be evaluated): glass is
/// only sampled.
pub fn bsdf_samples_lights(bsdf: &Bsdf) -> bool {
    bsdf.kind != BSDF_DIELECTRIC
}

fn alpha(bsdf: &Bsdf) -> f32 {
    bsdf.roughness.max(MIN_ALPHA)
}

/// `f(wo, wi) |cos θi|`; zero for glass.
pub fn bsdf_eval(bsdf: &Bsdf, wo: Vec3, wi: Vec3) -> Vec3 {
    match bsdf.kind {
        BSDF_DIFFUSE => lambert_eval(bsdf.color, wo, wi),
        BSDF_CONDUCTOR => rough_conductor_eval(bsdf.color, alpha(bsdf), wo, wi),
        BSDF_PLASTIC => rough_plastic_eval(bsdf.color, alpha(bsdf), bsdf.ior, wo, wi),
        _ => Vec3::ZERO,
    }
}

/// The density with which `bsdf_sample` draws `wi`; zero for glass.
pub fn bsdf_pdf(bsdf: &Bsdf, wo: Vec3, wi: Vec3) -> f32 {
    match bsdf.kind {
        BSDF_DIFFUSE => lambert_pdf(wo, wi),
        BSDF_CONDUCTOR => rough_conductor_pdf(alpha(bsdf), wo, wi),
        BSDF_PLASTIC => rough_plastic_pdf(bsdf.color, alpha(bsdf), bsdf.ior, wo, wi),
        _ => 0.0,
    }
}

/// A direction from three uniform numbers.
pub fn bsdf_sample(bsdf: &Bsdf, wo: Vec3, u: Vec3) -> BsdfSample {
    match bsdf.kind {
        BSDF_DIFFUSE => lambert_sample(bsdf.color, wo, u.xy()),
        BSDF_CONDUCTOR => rough_conductor_sample(bsdf.color, alpha(bsdf), wo, u.xy()),
        BSDF_PLASTIC => rough_plastic_sample(bsdf.color, alpha(bsdf), bsdf.ior, wo, u),
        _ => {
            let roughness = if bsdf.roughness > 0.0 { alpha(bsdf) } else { 0.0 };
            dielectric_sample(bsdf.color, roughness, bsdf.ior, wo, u)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::tests::halton;
    use crate::sampling::{UNIFORM_SPHERE_PDF, uniform_sphere};

    fn opaque() -> [Bsdf; 6] {
        let color = Vec3::new(0.9, 0.6, 0.3);
        [
            Bsdf { kind: BSDF_DIFFUSE, color, roughness: 0.0, ior: 1.0 },
            Bsdf { kind: BSDF_CONDUCTOR, color, roughness: 0.2, ior: 1.0 },
            Bsdf { kind: BSDF_CONDUCTOR, color: Vec3::ONE, roughness: 0.7, ior: 1.0 },
            Bsdf { kind: BSDF_PLASTIC, color, roughness: 0.15, ior: 1.5 },
            Bsdf { kind: BSDF_PLASTIC, color: Vec3::ONE, roughness: 0.6, ior: 1.5 },
            Bsdf { kind: BSDF_PLASTIC, color: Vec3::ONE, roughness: 0.05, ior: 1.9 },
        ]
    }

    fn views() -> [Vec3; 3] {
        [Vec3::Z, Vec3::new(0.5, 0.1, 0.7).normalize(), Vec3::new(-0.9, 0.2, 0.15).normalize()]
    }

    fn pick(i: u32) -> f32 {
        ((i as f32 + 0.5) * 0.618_034).fract()
    }

    #[test]
    fn evaluation_is_reciprocal() {
        for bsdf in opaque() {
            for i in 0..500 {
                let (a, b) = (uniform_sphere(halton(i)), uniform_sphere(halton(i + 7919)));
                let (a, b) = (Vec3::new(a.x, a.y, a.z.abs()), Vec3::new(b.x, b.y, b.z.abs()));
                // f(a, b) = f(b, a): compare f cos θi / cos θi both ways.
                let forward = bsdf_eval(&bsdf, a, b) / b.z.max(1e-4);
                let backward = bsdf_eval(&bsdf, b, a) / a.z.max(1e-4);
                let bound = 1e-3 * forward.max_element().max(1.0);
                assert!(
                    (forward - backward).abs().max_element() <= bound,
                    "{bsdf:?} {a} {b}: {forward} {backward}"
                );
            }
        }
    }

    #[test]
    fn no_bsdf_reflects_more_than_arrives() {
        // The albedo ∫ f cos θi dωi, estimated by sampling (weights) and by uniform directions.
        for bsdf in opaque() {
            for wo in views() {
                let count = 40_000;
                let sampled: Vec3 = (0..count)
                    .map(|i| {
                        let u = halton(i);
                        bsdf_sample(&bsdf, wo, Vec3::new(u.x, u.y, pick(i))).weight
                    })
                    .sum::<Vec3>()
                    / count as f32;
                let uniform: Vec3 = (0..count * 4)
                    .map(|i| bsdf_eval(&bsdf, wo, uniform_sphere(halton(i))) / UNIFORM_SPHERE_PDF)
                    .sum::<Vec3>()
                    / (count * 4) as f32;
                assert!(sampled.max_element() <= 1.0 + 1e-3, "{bsdf:?} at {wo}: {sampled}");
                assert!(
                    (sampled - uniform).abs().max_element() < 0.03,
                    "{bsdf:?} at {wo}: {sampled} against {uniform}"
                );
            }
        }
    }

    #[test]
    fn each_pdf_integrates_to_one_and_matches_its_samples() {
        for bsdf in opaque() {
            for wo in views() {
                let count = 200_000;
                let total: f32 = (0..count)
                    .map(|i| bsdf_pdf(&bsdf, wo, uniform_sphere(halton(i))) / UNIFORM_SPHERE_PDF)
                    .sum::<f32>()
                    / count as f32;
                // Visible-normal reflections below the horizon are lost, so at most one (a third of
                // them head on at alpha 0.7: GGX puts that share of normals beyond 45 degrees).
                assert!(total <= 1.02 && total > 0.6, "{bsdf:?} at {wo}: {total}");
                for i in 0..200 {
                    let u = halton(i);
                    let s = bsdf_sample(&bsdf, wo, Vec3::new(u.x, u.y, pick(i)));
                    if s.weight != Vec3::ZERO {
                        let pdf = bsdf_pdf(&bsdf, wo, s.direction);
                        assert!((s.pdf - pdf).abs() <= 1e-3 * pdf, "{bsdf:?}: {} against {pdf}", s.pdf);
                        let weight = bsdf_eval(&bsdf, wo, s.direction) / pdf;
                        assert!(
                            (s.weight - weight).abs().max_element() <= 1e-3 * weight.max_element().max(1.0)
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn a_white_diffuse_surface_reflects_everything() {
        let white = Bsdf { kind: BSDF_DIFFUSE, color: Vec3::ONE, roughness: 0.0, ior: 1.0 };
        for wo in views() {
            let count = 100_000;
            let albedo: f32 = (0..count)
                .map(|i| bsdf_eval(&white, wo, uniform_sphere(halton(i))).x / UNIFORM_SPHERE_PDF)
                .sum::<f32>()
                / count as f32;
            assert!((albedo - 1.0).abs() < 0.01, "{albedo}");
        }
    }

    #[test]
    fn glass_is_one_sided_and_only_sampled() {
        let glass = Bsdf { kind: BSDF_DIELECTRIC, color: Vec3::ONE, roughness: 0.0, ior: 1.5 };
        assert!(!bsdf_is_two_sided(&glass) && !bsdf_samples_lights(&glass));
        assert_eq!(bsdf_eval(&glass, Vec3::Z, Vec3::Z), Vec3::ZERO);
        assert!(bsdf_sample(&glass, Vec3::Z, Vec3::new(0.5, 0.5, 0.5)).delta);
        assert!(opaque().iter().all(|b| bsdf_is_two_sided(b) && bsdf_samples_lights(b)));
    }
}
