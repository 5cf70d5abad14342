//! How far a shadow or reflection ray leaving a patch ignores what it meets. Twin of
//! `shaders/self_clearance.glsl`.
//!
//! Neighbouring patches overlap by design (each reaches its neighbours' footprints), and
//! where the scan is noisy a neighbour's surface lies a little above the patch that was hit.
//! A secondary ray offset only by the scene-wide epsilon then hits that neighbour, and the
//! surface shadows itself in dark specks along the seams. Ignoring hits closer than a fraction
//! of the hit patch's own support radius skips the neighbours and nothing bigger.

/// The fraction of the support radius `d_i` that secondary rays ignore.
pub const SELF_CLEARANCE_FRACTION: f32 = 1.0;

/// The `t_min` of secondary rays leaving a patch of world-space support radius `radius`.
pub fn self_clearance(radius: f32) -> f32 {
    SELF_CLEARANCE_FRACTION * radius
}

/// The path integrator's rays leave a patch differently: skipping every hit within a support
/// radius along the ray lets a ray through a wall that lies closer than that (an adjacent
/// wall near an edge, the far side of a concave surface met at a grazing angle), and light
/// leaks into closed shapes. They start off the surface along its normal by this share of
/// the clearance instead, and skip nothing: that clears the neighbours' fitted surfaces, which
/// lie much closer together than the points' own noise.
pub const PATH_OFFSET_SHARE: f32 = 0.05;

/// How far along the normal a path integrator's ray leaving a patch of clearance `clearance`
/// starts (at least the scene's `epsilon`, the whole offset for a triangle).
pub fn path_ray_offset(clearance: f32, epsilon: f32) -> f32 {
    (PATH_OFFSET_SHARE * clearance).max(epsilon)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_glsl_twin_uses_the_same_fraction() {
        let glsl = include_str!("../shaders/self_clearance.glsl");
        let expected = format!("const float SELF_CLEARANCE_FRACTION = {SELF_CLEARANCE_FRACTION:?};");
        assert!(glsl.contains(&expected), "shaders/self_clearance.glsl must declare `{expected}`");
    }

    #[test]
    fn the_glsl_twin_offsets_paths_by_the_same_share() {
        let glsl = include_str!("../shaders/self_clearance.glsl");
        let expected = format!("const float PATH_OFFSET_SHARE = {PATH_OFFSET_SHARE:?};");
        assert!(glsl.contains(&expected), "shaders/self_clearance.glsl must declare `{expected}`");
        assert_eq!(path_ray_offset(0.0, 1e-4), 1e-4, "a triangle's rays leave by the epsilon");
        assert_eq!(path_ray_offset(1.0, 1e-4), PATH_OFFSET_SHARE);
    }

    #[test]
    fn clearance_scales_with_the_radius() {
        assert_eq!(self_clearance(0.0), 0.0);
        assert!((self_clearance(2.0) - 2.0 * self_clearance(1.0)).abs() < 1e-6);
    }
}
