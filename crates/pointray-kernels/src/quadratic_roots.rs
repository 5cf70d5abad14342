//! Real roots of `a t² + b t + c = 0`, robustly. Twin of `shaders/quadratic_roots.glsl`.

/// Below this `|a| / |b|` the equation is solved as linear. The dropped root is then at
/// `|t| >= |b / a| > 1e6` ray units, beyond any scene we render, and dividing by such an
/// `a` could overflow or give NaN.
pub const LINEAR_THRESHOLD: f32 = 1e-6;

/// Up to two real roots in ascending order; `roots[..count]` are valid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadraticRoots {
    pub count: u32,
    pub roots: [f32; 2],
}

impl QuadraticRoots {
    const NONE: Self = Self { count: 0, roots: [0.0; 2] };

    /// The valid roots, ascending.
    pub fn as_slice(&self) -> &[f32] {
        &self.roots[..self.count as usize]
    }
}

/// Solves `a t² + b t + c = 0` without catastrophic cancellation:
/// `q = -(b + sign(b) √disc) / 2`, roots `q / a` and `c / q`.
/// A degenerate equation (`a` and `b` both zero) has no roots reported, even when `c = 0`:
/// for a ray that would mean lying inside the surface, which is not a hit.
pub fn quadratic_roots(a: f32, b: f32, c: f32) -> QuadraticRoots {
    if a.abs() <= LINEAR_THRESHOLD * b.abs() {
        return linear_root(b, c);
    }
    let discriminant = b * b - 4.0 * a * c;
    if discriminant < 0.0 {
        return QuadraticRoots::NONE;
    }
    // `sign(b)` with sign(0) = +1, spelled out because GLSL's sign(0) is 0.
    let sign_b = if b >= 0.0 { 1.0 } else { -1.0 };
    let q = -0.5 * (b + sign_b * discriminant.sqrt());
    let first = q / a;
    // q = 0 only when b = 0 and disc = 0, which forces c = 0: a double root at 0.
    let second = if q != 0.0 { c / q } else { first };
    QuadraticRoots { count: 2, roots: [first.min(second), first.max(second)] }
}

fn linear_root(b: f32, c: f32) -> QuadraticRoots {
    if b == 0.0 {
        return QuadraticRoots::NONE;
    }
    let t = -c / b;
    QuadraticRoots { count: 1, roots: [t, t] }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_known_roots_come_back_sorted() {
        // (t - 1)(t - 3) = t² - 4t + 3
        assert_eq!(quadratic_roots(1.0, -4.0, 3.0).as_slice(), &[1.0, 3.0]);
        // -2 (t + 2)(t - 0.5) = -2t² - 3t + 2
        assert_eq!(quadratic_roots(-2.0, -3.0, 2.0).as_slice(), &[-2.0, 0.5]);
    }

    #[test]
    fn no_real_roots_when_the_discriminant_is_negative() {
        assert_eq!(quadratic_roots(1.0, 0.0, 1.0).count, 0);
    }

    #[test]
    fn a_double_root_at_zero_is_found() {
        assert_eq!(quadratic_roots(2.0, 0.0, 0.0).as_slice(), &[0.0, 0.0]);
    }

    #[test]
    fn tiny_a_is_solved_as_linear() {
        let roots = quadratic_roots(1e-12, 2.0, -4.0);
        assert_eq!(roots.as_slice(), &[2.0]);
        let exactly_linear = quadratic_roots(0.0, -0.5, 1.0);
        assert_eq!(exactly_linear.as_slice(), &[2.0]);
    }

    #[test]
    fn degenerate_equations_have_no_roots() {
        assert_eq!(quadratic_roots(0.0, 0.0, 1.0).count, 0);
        assert_eq!(quadratic_roots(0.0, 0.0, 0.0).count, 0);
    }

    #[test]
    fn the_small_root_keeps_its_precision_when_b_dominates() {
        // Roots 1e-4 and 1e4: the naive formula loses the small one to cancellation in f32.
        let (small, large) = (1e-4f32, 1e4f32);
        let roots = quadratic_roots(1.0, -(small + large), small * large);
        assert!((roots.roots[0] - small).abs() / small < 1e-5, "{roots:?}");
        assert!((roots.roots[1] - large).abs() / large < 1e-5, "{roots:?}");
    }
}
