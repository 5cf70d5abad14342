//! A patch's tangent frame in a normal and an angle. Twin of `shaders/tangent_frame.glsl`.
//!
//! A frame is stored in one word: the normal octahedrally in two snorm11 (the low 22 bits) and
//! the first tangent as its angle from a fixed basis of the normal in unorm10 over half a turn
//! (the high 10 bits; an elliptical support is symmetric under a half turn). The steps are
//! at most 0.09° of normal and 0.09° of angle. `prep` fits every patch in the frame these
//! decode to, so the quantisation moves the frame but never puts the fit out of step with it.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

/// The right-handed orthonormal frame `(t1, t2, n)` of a patch, with `t2 = n × t1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentFrame {
    pub t1: Vec3,
    pub t2: Vec3,
    pub n: Vec3,
}

impl TangentFrame {
    /// The frame of unit normal `n` whose first tangent lies `angle` radians from the
    /// normal's fixed basis vector (`normal_basis`).
    pub fn from_normal_and_angle(n: Vec3, angle: f32) -> Self {
        let (b1, b2) = normal_basis(n);
        let t1 = (angle.cos() * b1 + angle.sin() * b2).normalize();
        Self { t1, t2: n.cross(t1), n }
    }

    /// A world offset from the frame's origin to local `(u, v, w)`.
    pub fn to_local(&self, offset: Vec3) -> Vec3 {
        Vec3::new(offset.dot(self.t1), offset.dot(self.t2), offset.dot(self.n))
    }

    /// Local `(u, v, w)` to a world offset from the frame's origin.
    pub fn to_world(&self, local: Vec3) -> Vec3 {
        local.x * self.t1 + local.y * self.t2 + local.z * self.n
    }
}

/// Two unit tangents of unit normal `n`, without any branch on its direction that could lose
/// precision (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
pub fn normal_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// A unit vector to the octahedral square `[-1, 1]²`.
pub fn octahedral_encode(n: Vec3) -> Vec2 {
    let p = Vec2::new(n.x, n.y) / (n.x.abs() + n.y.abs() + n.z.abs());
    if n.z >= 0.0 { p } else { (Vec2::ONE - Vec2::new(p.y, p.x).abs()) * sign_not_zero(p) }
}

/// The unit vector of octahedral codes `(a, b)`, the inverse of `octahedral_encode` scaled by
/// `NORMAL_STEPS`. The third coordinate comes from the integers, so that its sign, which picks
/// the fold here and the normal's basis in `normal_basis`, is exact on the CPU and the GPU
/// alike, however each rounds a division: near the equator a rounded `1 - |x| - |y|` could
/// fall either side of zero and turn the tangent.
pub fn octahedral_decode(a: i32, b: i32) -> Vec3 {
    let steps = NORMAL_STEPS as i32;
    let (a, b) = (a.clamp(-steps, steps), b.clamp(-steps, steps));
    let z = (steps - a.abs() - b.abs()) as f32 / NORMAL_STEPS;
    let (x, y) = (a as f32 / NORMAL_STEPS, b as f32 / NORMAL_STEPS);
    let fold = (-z).max(0.0);
    let x = x + if x >= 0.0 { -fold } else { fold };
    let y = y + if y >= 0.0 { -fold } else { fold };
    Vec3::new(x, y, z).normalize()
}

fn sign_not_zero(v: Vec2) -> Vec2 {
    Vec2::new(if v.x >= 0.0 { 1.0 } else { -1.0 }, if v.y >= 0.0 { 1.0 } else { -1.0 })
}

/// The largest magnitude of a snorm11 octahedral coordinate, and of the unorm10 angle.
const NORMAL_STEPS: f32 = 1023.0;
const ANGLE_STEPS: f32 = 1023.0;
const ANGLE_SHIFT: u32 = 22;

/// The stored normal bits (the frame word's low 22) of unit normal `n`: of the four codes
/// around its octahedral point, the one that decodes nearest to it (Cigolle et al. 2014), which
/// halves the error of rounding each coordinate alone.
pub fn pack_normal(n: Vec3) -> u32 {
    let e = octahedral_encode(n).clamp(Vec2::NEG_ONE, Vec2::ONE) * NORMAL_STEPS;
    let step = |v: f32, up: f32| (v.floor() + up).min(NORMAL_STEPS) as i32;
    let candidates = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)].map(|(dx, dy)| {
        let bits = normal_bits(step(e.x, dx), step(e.y, dy));
        (bits, unpack_normal(bits).dot(n))
    });
    candidates.into_iter().max_by(|a, b| a.1.total_cmp(&b.1)).expect("four codes").0
}

/// The normal bits of octahedral codes `(a, b)`, each in `[-1023, 1023]`: two snorm11 in the
/// low 22 bits.
pub fn normal_bits(a: i32, b: i32) -> u32 {
    (a as u32 & 0x7ff) | ((b as u32 & 0x7ff) << 11)
}

/// The normal a frame word's low 22 bits decode to.
pub fn unpack_normal(word: u32) -> Vec3 {
    // Sign-extends the 11 bits, as GLSL's arithmetic shift of an int does.
    let code = |bits: u32| ((bits << 21) as i32) >> 21;
    octahedral_decode(code(word), code(word >> 11))
}

/// The frame word of unit normal `n` with first tangent `t` (in `n`'s plane): the tangent's
/// angle is taken from the stored normal's basis, so that it decodes to the axis nearest `t`.
pub fn pack_frame(n: Vec3, t: Vec3) -> u32 {
    let normal = pack_normal(n);
    let angle = (tangent_angle_fraction(unpack_normal(normal), t) * ANGLE_STEPS).round() as u32;
    normal | (angle << ANGLE_SHIFT)
}

/// The frame a frame word decodes to.
pub fn unpack_frame(word: u32) -> TangentFrame {
    let fraction = (word >> ANGLE_SHIFT) as f32 / ANGLE_STEPS;
    TangentFrame::from_normal_and_angle(unpack_normal(word), fraction * PI)
}

/// The angle in `[0, π)` of tangent `t` (in the plane of `n`) from `normal_basis(n).0`,
/// as a fraction of π: what the record stores.
pub fn tangent_angle_fraction(n: Vec3, t: Vec3) -> f32 {
    let (b1, b2) = normal_basis(n);
    let angle = t.dot(b2).atan2(t.dot(b1)).rem_euclid(PI);
    (angle / PI).min(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fibonacci_directions(count: usize) -> impl Iterator<Item = Vec3> {
        (0..count).map(move |i| {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / count as f32;
            let phi = i as f32 * 2.399_963;
            let r = (1.0 - z * z).sqrt();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        })
    }

    fn assert_orthonormal(frame: TangentFrame) {
        for (a, b) in [(frame.t1, frame.t2), (frame.t1, frame.n), (frame.t2, frame.n)] {
            assert!(a.dot(b).abs() < 1e-5, "{frame:?} not orthogonal");
        }
        for axis in [frame.t1, frame.t2, frame.n] {
            assert!((axis.length() - 1.0).abs() < 1e-5, "{frame:?} not unit");
        }
        assert!((frame.t1.cross(frame.t2) - frame.n).length() < 1e-5, "{frame:?} not right-handed");
    }

    #[test]
    fn stored_normals_stay_within_a_tenth_of_a_degree() {
        for n in fibonacci_directions(5000).chain([Vec3::Z, -Vec3::Z, Vec3::X, -Vec3::Y]) {
            let error = unpack_normal(pack_normal(n)).cross(n).length().asin().to_degrees();
            assert!(error < 0.09, "{n} came back {error}° off");
        }
        for axis in [Vec3::Z, -Vec3::Z, Vec3::X, -Vec3::Y] {
            assert_eq!(unpack_normal(pack_normal(axis)), axis, "the axes are stored exactly");
        }
    }

    #[test]
    fn codes_on_the_equator_decode_to_z_of_exactly_zero() {
        for a in -1023i32..=1023 {
            for b in [1023 - a.abs(), a.abs() - 1023] {
                let n = unpack_normal(normal_bits(a, b));
                assert!(n.z == 0.0 && n.z.is_sign_positive(), "({a}, {b}) -> {n}");
            }
        }
    }

    #[test]
    fn stored_frames_keep_their_tangent_within_a_fifth_of_a_degree() {
        for (i, n) in fibonacci_directions(2000).enumerate() {
            let (b1, b2) = normal_basis(n);
            let angle = i as f32 * 0.731;
            let t = angle.cos() * b1 + angle.sin() * b2;
            let frame = unpack_frame(pack_frame(n, t));
            let off = frame.n.cross(n).length().asin().to_degrees();
            assert!(off < 0.09, "{n}: normal {off}° off");
            // The axis, not its sense: the support is symmetric under a half turn.
            let error = frame.t1.dot(t).abs().min(1.0).acos().to_degrees();
            assert!(error < 0.2, "{n}, tangent {t}: {error}° off");
        }
    }

    #[test]
    fn frames_are_orthonormal_for_every_direction_and_angle() {
        for (i, n) in fibonacci_directions(2000).chain([Vec3::Z, -Vec3::Z, -Vec3::X]).enumerate() {
            assert_orthonormal(TangentFrame::from_normal_and_angle(n, i as f32 * 0.37));
        }
    }

    #[test]
    fn a_tangent_angle_round_trips_to_the_same_axis() {
        let n = Vec3::new(0.3, -0.4, 0.8).normalize();
        let (b1, b2) = normal_basis(n);
        let t = (0.6 * b1 + 0.8 * b2).normalize();
        let frame = TangentFrame::from_normal_and_angle(n, tangent_angle_fraction(n, t) * PI);
        assert!(frame.t1.dot(t).abs() > 0.999_999);
        // A tangent a half turn away gives the same axis.
        let opposite = TangentFrame::from_normal_and_angle(n, tangent_angle_fraction(n, -t) * PI);
        assert!(opposite.t1.dot(t).abs() > 0.999_999);
    }
}
