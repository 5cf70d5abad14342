//! The axis-aligned box of a patch (METHOD.md §2.4): the paper's cube, or a tight box
//! around the patch surface over its support ellipse.

use std::sync::LazyLock;

use crate::prep_settings::BoxKind;
use glam::{Vec2, Vec3};
use pointray_kernels::{Aabb, Patch, PatchHot};

/// Rim samples of the tight box.
const RIM_SAMPLES: usize = 24;

/// Padding of the tight box, as a fraction of `d_i`. It covers what the samples miss:
/// the rim polygon falls short of the ellipse by at most `d_u (1 - cos(π/24)) ≈ 0.0086 d_u`,
/// and the height between rim samples deviates by a similar fraction of the height range.
const TIGHT_PADDING: f32 = 0.02;

pub fn patch_box(patch: &PatchHot, kind: BoxKind) -> Aabb {
    match kind {
        BoxKind::Cube => Aabb::cube(patch.origin(), patch.radius()),
        BoxKind::Tight => tight_box(&patch.decode()),
    }
}

/// The box around the centre, the rim and (when over the support) the critical point
/// of `f`, where an interior extremum lies, padded by `TIGHT_PADDING d_u`.
fn tight_box(patch: &Patch) -> Aabb {
    let coefficients = patch.coefficients;
    let interior = critical_point(&coefficients).filter(|&c| patch.supports(c)).unwrap_or(Vec2::ZERO);
    let (low, high) = rim_extent(patch);
    let (min, max) = [Vec2::ZERO, interior].into_iter().fold((low, high), |(min, max), uv| {
        let world = patch.to_world(uv.extend(evaluate(&coefficients, uv.x, uv.y)));
        (min.min(world), max.max(world))
    });
    let pad = Vec3::splat(TIGHT_PADDING * patch.radii.x);
    Aabb::new(min - pad, max + pad)
}

/// The lowest and highest world coordinates of the rim samples. Written over fixed arrays,
/// coordinate by coordinate, so that the compiler computes eight samples at a time; each
/// sample's arithmetic is `Patch::to_world` of `evaluate`'s height, so the box is the one a
/// sample-by-sample loop gives.
fn rim_extent(patch: &Patch) -> (Vec3, Vec3) {
    let (t1, t2, n, origin) = (patch.frame.t1, patch.frame.t2, patch.frame.n, patch.origin);
    let mut world = [[0.0f32; RIM_SAMPLES]; 3];
    for (s, direction) in RIM_DIRECTIONS.iter().enumerate() {
        let (u, v) = (direction.x * patch.radii.x, direction.y * patch.radii.y);
        let w = evaluate(&patch.coefficients, u, v);
        for axis in 0..3 {
            world[axis][s] = origin[axis] + (u * t1[axis] + v * t2[axis] + w * n[axis]);
        }
    }
    let extent = |samples: &[f32; RIM_SAMPLES]| {
        samples.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(low, high), &x| (low.min(x), high.max(x)))
    };
    let [(x_low, x_high), (y_low, y_high), (z_low, z_high)] = world.each_ref().map(extent);
    (Vec3::new(x_low, y_low, z_low), Vec3::new(x_high, y_high, z_high))
}

/// Unit directions to the rim samples, computed once: 24 sines and cosines per patch were
/// most of the boxes' time. The same values as computed in place, so the same boxes.
static RIM_DIRECTIONS: LazyLock<[Vec2; RIM_SAMPLES]> = LazyLock::new(|| {
    std::array::from_fn(|i| {
        let angle = std::f32::consts::TAU * i as f32 / RIM_SAMPLES as f32;
        Vec2::new(angle.cos(), angle.sin())
    })
});

/// Evaluates `f(u, v) = c0 + c1 u + c2 v + c3 u² + c4 uv + c5 v²`.
pub fn evaluate(c: &[f32; 6], u: f32, v: f32) -> f32 {
    c[0] + c[1] * u + c[2] * v + c[3] * u * u + c[4] * u * v + c[5] * v * v
}

/// Where the gradient of `f` vanishes, if the quadratic part is not singular.
fn critical_point(c: &[f32; 6]) -> Option<Vec2> {
    // ∇f = 0:  [2c3  c4 ] [u]   [-c1]
    //          [c4   2c5] [v] = [-c2]
    let determinant = 4.0 * c[3] * c[5] - c[4] * c[4];
    let scale = c[3].abs().max(c[4].abs()).max(c[5].abs());
    if determinant.abs() <= 1e-6 * scale * scale || scale == 0.0 {
        return None;
    }
    let u = (-c[1] * 2.0 * c[5] + c[2] * c[4]) / determinant;
    let v = (-c[2] * 2.0 * c[3] + c[1] * c[4]) / determinant;
    Some(Vec2::new(u, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_patch() -> PatchHot {
        let n = Vec3::new(0.3, -0.2, 1.0).normalize();
        let frame = pointray_kernels::PackedTangentFrame::new(n, n.any_orthonormal_vector());
        PatchHot::new(
            Vec3::new(1.0, 2.0, 3.0),
            frame,
            Vec2::new(0.3, 0.12),
            [0.01, 0.2, -0.1, 1.5, -0.7, 2.0],
        )
    }

    #[test]
    fn cube_is_the_papers_box() {
        let patch = sample_patch();
        let cube = patch_box(&patch, BoxKind::Cube);
        assert_eq!(cube, Aabb::cube(patch.origin(), 0.3));
    }

    #[test]
    fn tight_box_contains_the_whole_patch_surface_over_its_support() {
        let hot = sample_patch();
        let tight = patch_box(&hot, BoxKind::Tight);
        let patch = hot.decode();
        let coefficients = patch.coefficients;
        for ring in 0..=20 {
            for step in 0..97 {
                let scale = ring as f32 / 20.0;
                let angle = step as f32 * std::f32::consts::TAU / 97.0;
                let (u, v) = (patch.radii.x * scale * angle.cos(), patch.radii.y * scale * angle.sin());
                let world = patch.to_world(Vec3::new(u, v, evaluate(&coefficients, u, v)));
                assert!(tight.contains(world), "{world} outside {tight:?}");
            }
        }
        let extent = Vec3::from(tight.max) - Vec3::from(tight.min);
        assert!(extent.max_element() < 2.2 * patch.radii.x);
    }

    #[test]
    fn box_codes_round_trip() {
        for kind in [BoxKind::Cube, BoxKind::Tight] {
            assert_eq!(BoxKind::from_code(kind.code()), Some(kind));
        }
        assert_eq!(BoxKind::from_code(7), None);
    }
}
