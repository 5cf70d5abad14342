//! The normal of a patch at local `(u, v)` (METHOD.md §3, closest hit).
//! Twin of `shaders/patch_normal.glsl`.

use glam::{Vec2, Vec3};

use crate::layout::Patch;

/// The gradient of `w - f(u, v)`, local `(-f_u, -f_v, 1)`, in the patch's space
/// (object space), unit length. It points to the side the patch's normal `n_i` faces;
/// callers face it toward the viewer with `face_forward`.
pub fn patch_normal(patch: &Patch, uv: Vec2) -> Vec3 {
    let [_, c1, c2, c3, c4, c5] = patch.coefficients;
    let f_u = c1 + 2.0 * c3 * uv.x + c4 * uv.y;
    let f_v = c2 + c4 * uv.x + 2.0 * c5 * uv.y;
    patch.direction_to_world(Vec3::new(-f_u, -f_v, 1.0)).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::PatchHot;

    /// A frame with normal +Y and first tangent +X, so `t2 = Y × X = -Z`.
    fn y_up_patch(coefficients: [f32; 6]) -> Patch {
        PatchHot::isotropic(Vec3::new(1.0, 2.0, 3.0), Vec3::X, Vec3::Y, coefficients, 1.0).decode()
    }

    #[test]
    fn a_flat_patch_has_its_frame_normal() {
        let normal = patch_normal(&y_up_patch([0.3, 0.0, 0.0, 0.0, 0.0, 0.0]), Vec2::new(0.4, -0.2));
        assert!((normal - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn a_tilted_plane_leans_its_normal_against_the_slope() {
        // w = 0.5 u: gradient normal (-0.5, 0, 1) locally, i.e. -0.5 X + 1 Y in the world.
        let normal = patch_normal(&y_up_patch([0.0, 0.5, 0.0, 0.0, 0.0, 0.0]), Vec2::ZERO);
        assert!((normal - Vec3::new(-0.5, 1.0, 0.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn a_paraboloid_normal_matches_its_analytic_gradient() {
        // w = u² + v²: at (u, v) = (0.5, -0.25) the gradient is (1, -0.5), so the local
        // normal is (-1, 0.5, 1) and in the world -1 X + 0.5 (-Z) + 1 Y.
        let normal = patch_normal(&y_up_patch([0.0, 0.0, 0.0, 1.0, 0.0, 1.0]), Vec2::new(0.5, -0.25));
        assert!((normal - Vec3::new(-1.0, 1.0, -0.5).normalize()).length() < 1e-6);
    }
}
