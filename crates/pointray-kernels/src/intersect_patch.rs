//! A ray against one quadratic patch (METHOD.md §3, intersection steps 1-3).
//! Twin of `shaders/intersect_patch.glsl`.
//!
//! **The box test uses the patch's own cube `[p - d_u, p + d_u]`**, computed from the hot
//! record, not the stored `Aabb`: the test then reads only the hot record, as the paper's
//! hot/cold split intends (METHOD.md §2.7). The stored box is that cube or (the default) a
//! tight box around the patch over its support ellipse, which the cube contains; the support
//! test then decides.

use glam::{Vec2, Vec3};

use crate::layout::Patch;
use crate::quadratic_roots::quadratic_roots;
use crate::ray::Ray;

/// Which roots on a patch's quadratic count as hits (METHOD.md §3, step 3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(u32)]
pub enum PatchAcceptance {
    /// The hit lies inside the patch's cube box (the paper's test).
    Box = 0,
    /// The hit lies inside the box and over the patch's support, `(u / d_u)² + (v / d_v)² <= 1`
    /// (a disk when the patch is isotropic). The default: against the meshes it has fewer false
    /// surfaces and smaller depth and normal errors than the box test, with no more holes
    /// (bench/FIDELITY.md).
    #[default]
    Disk = 1,
}

impl PatchAcceptance {
    /// The value the shaders receive (`ACCEPTANCE_BOX`, `ACCEPTANCE_DISK`).
    pub const fn code(self) -> u32 {
        self as u32
    }

    /// The name scene files and command lines use.
    pub const fn name(self) -> &'static str {
        match self {
            PatchAcceptance::Box => "box",
            PatchAcceptance::Disk => "disk",
        }
    }
}

impl std::str::FromStr for PatchAcceptance {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, String> {
        match name {
            "box" => Ok(PatchAcceptance::Box),
            "disk" => Ok(PatchAcceptance::Disk),
            other => Err(format!("unknown acceptance test `{other}` (expected `box` or `disk`)")),
        }
    }
}

/// Where a ray meets a patch: ray parameter and patch-local `(u, v)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchHit {
    pub t: f32,
    pub uv: Vec2,
}

/// The smallest root in `[t_min, t_max]` of the ray against `w = f(u, v)` that passes
/// `acceptance`. Ray and patch must be in the same space; the direction need not be
/// unit length (`t` is in the ray's own parameter).
pub fn intersect_patch(
    ray: &Ray,
    patch: &Patch,
    t_min: f32,
    t_max: f32,
    acceptance: PatchAcceptance,
) -> Option<PatchHit> {
    let o = patch.to_local(ray.origin);
    let d = patch.direction_to_local(ray.direction);
    let [a, b, c] = patch_quadratic(patch, o, d);
    let roots = quadratic_roots(a, b, c);
    roots.as_slice().iter().copied().filter(|t| (t_min..=t_max).contains(t)).find_map(|t| {
        let uv = Vec2::new(o.x + t * d.x, o.y + t * d.y);
        accepts(ray.at(t), uv, patch, acceptance).then_some(PatchHit { t, uv })
    })
}

/// `A, B, C` of `A t² + B t + C = 0` for the local ray `o + t d` against `w = f(u, v)`.
fn patch_quadratic(patch: &Patch, o: Vec3, d: Vec3) -> [f32; 3] {
    let [c0, c1, c2, c3, c4, c5] = patch.coefficients;
    let a = -(c3 * d.x * d.x + c4 * d.x * d.y + c5 * d.y * d.y);
    let b = d.z
        - (c1 * d.x + c2 * d.y + 2.0 * c3 * o.x * d.x + c4 * (o.x * d.y + o.y * d.x) + 2.0 * c5 * o.y * d.y);
    let f = c0 + c1 * o.x + c2 * o.y + c3 * o.x * o.x + c4 * o.x * o.y + c5 * o.y * o.y;
    [a, b, o.z - f]
}

fn accepts(point: Vec3, uv: Vec2, patch: &Patch, acceptance: PatchAcceptance) -> bool {
    let in_box = (point - patch.origin).abs().cmple(Vec3::splat(patch.radii.x)).all();
    match acceptance {
        PatchAcceptance::Box => in_box,
        PatchAcceptance::Disk => in_box && patch.supports(uv),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::PatchHot;

    /// A patch at the origin with normal +Z and first tangent +X (so `t2 = +Y`).
    fn z_up_patch(coefficients: [f32; 6], radius: f32) -> Patch {
        PatchHot::isotropic(Vec3::ZERO, Vec3::X, Vec3::Z, coefficients, radius).decode()
    }

    /// `w = 0.5 u²`, a parabolic cylinder.
    fn parabola(radius: f32) -> Patch {
        z_up_patch([0.0, 0.0, 0.0, 0.5, 0.0, 0.0], radius)
    }

    fn hit(ray: Ray, patch: &Patch, acceptance: PatchAcceptance) -> Option<PatchHit> {
        intersect_patch(&ray, patch, 0.0, f32::INFINITY, acceptance)
    }

    #[test]
    fn a_ray_across_a_parabola_meets_it_at_the_known_roots() {
        // From u = -2 at height 0.5 along +u: 0.5 u² = 0.5 at u = -1 (t = 1) and u = 1 (t = 3).
        let ray = Ray::new(Vec3::new(-2.0, 0.0, 0.5), Vec3::X);
        let first = hit(ray, &parabola(2.0), PatchAcceptance::Box).expect("a hit");
        assert!((first.t - 1.0).abs() < 1e-6 && (first.uv - Vec2::new(-1.0, 0.0)).length() < 1e-6);
        let second =
            intersect_patch(&ray, &parabola(2.0), 1.5, 10.0, PatchAcceptance::Box).expect("far root");
        assert!((second.t - 3.0).abs() < 1e-5);
        assert!(intersect_patch(&ray, &parabola(2.0), 0.0, 0.9, PatchAcceptance::Box).is_none());
    }

    #[test]
    fn hits_in_a_rotated_frame_lie_on_the_surface() {
        let normal = Vec3::new(0.3, -0.5, 0.8).normalize();
        let tangent = normal.any_orthonormal_vector();
        let patch = PatchHot::isotropic(
            Vec3::new(1.0, 2.0, -1.0),
            tangent,
            normal,
            [0.01, 0.1, -0.2, 0.4, 0.3, -0.2],
            0.5,
        )
        .decode();
        let target = patch.to_world(Vec3::new(0.1, -0.2, 0.0));
        let origin = target + Vec3::new(0.5, 1.0, 2.0);
        let hit = hit(Ray::new(origin, (target - origin).normalize()), &patch, PatchAcceptance::Disk)
            .expect("a hit");
        let local = patch.to_local(origin + hit.t * (target - origin).normalize());
        let [c0, c1, c2, c3, c4, c5] = patch.coefficients;
        let (u, v) = (local.x, local.y);
        let f = c0 + c1 * u + c2 * v + c3 * u * u + c4 * u * v + c5 * v * v;
        assert!((local.z - f).abs() < 1e-5, "w {} vs f {f}", local.z);
        assert!((hit.uv - Vec2::new(u, v)).length() < 1e-5);
    }

    #[test]
    fn a_grazing_ray_touches_the_apex() {
        // Tangent to w = 0.5 u² at u = 0: a double root at t = 2.
        let grazing = hit(Ray::new(Vec3::new(-2.0, 0.0, 0.0), Vec3::X), &parabola(1.0), PatchAcceptance::Box);
        assert!((grazing.expect("a touching hit").t - 2.0).abs() < 1e-4);
        // Just above the apex the ray misses.
        let above = Ray::new(Vec3::new(-2.0, 0.0, 1e-3), Vec3::X);
        assert!(hit(above, &parabola(0.01), PatchAcceptance::Box).is_none());
    }

    #[test]
    fn rays_parallel_to_a_flat_patch_never_hit_it() {
        let flat = z_up_patch([0.0; 6], 1.0);
        let above = Ray::new(Vec3::new(-2.0, 0.0, 0.1), Vec3::X);
        let inside = Ray::new(Vec3::new(-2.0, 0.0, 0.0), Vec3::X);
        assert!(hit(above, &flat, PatchAcceptance::Box).is_none());
        assert!(hit(inside, &flat, PatchAcceptance::Box).is_none());
        // Nearly parallel: it meets the plane far outside the box.
        let nearly = Ray::new(Vec3::new(-2.0, 0.0, 0.1), Vec3::new(1.0, 0.0, -1e-4).normalize());
        assert!(hit(nearly, &flat, PatchAcceptance::Box).is_none());
    }

    #[test]
    fn near_zero_a_takes_the_linear_root() {
        // A tilted plane w = 0.5 u (A = 0 exactly), hit straight down at u = 0.4: w = 0.2.
        let tilted = z_up_patch([0.0, 0.5, 0.0, 0.0, 0.0, 0.0], 1.0);
        let down = Ray::new(Vec3::new(0.4, 0.0, 3.0), Vec3::NEG_Z);
        assert!((hit(down, &tilted, PatchAcceptance::Box).expect("a hit").t - 2.8).abs() < 1e-6);
        // Barely curved (A ~ 1e-9): the same answer, no overflow from the far root.
        let barely = z_up_patch([0.0, 0.5, 0.0, 1e-9, 0.0, 0.0], 1.0);
        let oblique = Ray::new(Vec3::new(0.0, 0.0, 3.0), Vec3::new(0.4, 0.0, -2.8).normalize());
        let t = hit(oblique, &barely, PatchAcceptance::Box).expect("a hit").t;
        assert!((t - Vec3::new(0.4, 0.0, -2.8).length()).abs() < 1e-5, "{t}");
    }

    #[test]
    fn a_ray_through_the_box_that_passes_over_the_patch_misses() {
        // The ray crosses the whole box at w = 0.9, but 0.5 u² = 0.9 only at |u| = 1.34 > 1.
        let over = Ray::new(Vec3::new(-3.0, 0.0, 0.9), Vec3::X);
        assert!(hit(over, &parabola(1.0), PatchAcceptance::Box).is_none());
        // A flat patch: the ray descends through the box but reaches w = 0 at v = 1.5 > 1.
        let past = Ray::new(Vec3::new(0.5, -1.0, 0.5), Vec3::new(0.0, 1.0, -0.2).normalize());
        assert!(hit(past, &z_up_patch([0.0; 6], 1.0), PatchAcceptance::Box).is_none());
    }

    #[test]
    fn the_disk_test_rejects_box_corners_the_box_test_accepts() {
        let flat = z_up_patch([0.0; 6], 1.0);
        let corner = Ray::new(Vec3::new(0.9, 0.9, 2.0), Vec3::NEG_Z);
        assert!(hit(corner, &flat, PatchAcceptance::Box).is_some());
        assert!(hit(corner, &flat, PatchAcceptance::Disk).is_none());
        let centre = Ray::new(Vec3::new(0.5, 0.5, 2.0), Vec3::NEG_Z);
        assert!(hit(centre, &flat, PatchAcceptance::Box).is_some());
        assert!(hit(centre, &flat, PatchAcceptance::Disk).is_some());
    }

    #[test]
    fn the_support_test_follows_the_ellipse() {
        let frame = crate::layout::PackedTangentFrame::new(Vec3::Z, Vec3::X);
        let ellipse = PatchHot::new(Vec3::ZERO, frame, glam::Vec2::new(1.0, 0.25), [0.0; 6]).decode();
        let down = |x: f32, y: f32| Ray::new(Vec3::new(x, y, 2.0), Vec3::NEG_Z);
        assert!(hit(down(0.9, 0.0), &ellipse, PatchAcceptance::Disk).is_some());
        assert!(hit(down(0.0, 0.3), &ellipse, PatchAcceptance::Disk).is_none());
        assert!(hit(down(0.0, 0.3), &ellipse, PatchAcceptance::Box).is_some());
    }

    #[test]
    fn t_is_in_the_rays_own_parameter_when_the_direction_is_not_unit() {
        let flat = z_up_patch([0.0; 6], 1.0);
        let scaled = Ray::new(Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 0.0, -4.0));
        assert!((hit(scaled, &flat, PatchAcceptance::Box).expect("a hit").t - 0.5).abs() < 1e-6);
    }
}
