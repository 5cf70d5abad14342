//! Fresnel reflectance and refraction. Twin of `shaders/fresnel.glsl`.

use glam::Vec3;

/// The reflectance of unpolarised light meeting a dielectric boundary at `cos_incident`
/// (≥ 0) with relative index `eta` = (index beyond) / (index on the incident side); 1 under
/// total internal reflection.
pub fn fresnel_dielectric(cos_incident: f32, eta: f32) -> f32 {
    let cos_i = cos_incident.clamp(0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (s * s + p * p)
}

/// Schlick's approximation for a conductor whose reflectance head on is `f0`.
pub fn fresnel_schlick(cos_incident: f32, f0: Vec3) -> Vec3 {
    let c = 1.0 - cos_incident.clamp(0.0, 1.0);
    let c5 = c * c * c * c * c;
    f0 + (Vec3::ONE - f0) * c5
}

/// The direction that `incident` (pointing away from the surface, on `normal`'s side,
/// both unit length) refracts into beyond the boundary of relative index `eta`; `None`
/// under total internal reflection.
pub fn refract_direction(incident: Vec3, normal: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = incident.dot(normal);
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-incident / eta + (cos_i / eta - cos_t) * normal)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn head_on_reflectance_is_the_squared_index_ratio() {
        for eta in [1.33f32, 1.5, 2.4, 1.0 / 1.5] {
            let expected = ((eta - 1.0) / (eta + 1.0)).powi(2);
            assert!((fresnel_dielectric(1.0, eta) - expected).abs() < 1e-6, "eta {eta}");
        }
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
    }

    #[test]
    fn grazing_light_is_reflected_and_total_internal_reflection_is_complete() {
        assert!(fresnel_dielectric(1e-4, 1.5) > 0.99);
        // From glass to air beyond the critical angle (asin(1/1.5) = 41.8°).
        assert_eq!(fresnel_dielectric(50f32.to_radians().cos(), 1.0 / 1.5), 1.0);
        assert!(
            refract_direction(
                Vec3::new(50f32.to_radians().sin(), 0.0, 50f32.to_radians().cos()),
                Vec3::Z,
                1.0 / 1.5
            )
            .is_none()
        );
    }

    #[test]
    fn refraction_obeys_snell_and_is_reversible() {
        let incident = Vec3::new(0.5, 0.0, 0.75f32.sqrt());
        let eta = 1.5;
        let refracted =
            refract_direction(incident, Vec3::Z, eta).expect("no total internal reflection entering glass");
        assert!((refracted.length() - 1.0).abs() < 1e-5 && refracted.z < 0.0);
        let (sin_i, sin_t) = (incident.x, -refracted.x);
        assert!((sin_i - eta * sin_t).abs() < 1e-5, "Snell: {sin_i} against {eta} x {sin_t}");
        let back = refract_direction(refracted, Vec3::NEG_Z, 1.0 / eta).expect("the way back refracts too");
        assert!((back - incident).length() < 1e-5);
    }

    #[test]
    fn schlick_runs_from_its_base_to_white() {
        let f0 = Vec3::new(0.9, 0.6, 0.2);
        assert_eq!(fresnel_schlick(1.0, f0), f0);
        assert!((fresnel_schlick(0.0, f0) - Vec3::ONE).length() < 1e-6);
    }
}
