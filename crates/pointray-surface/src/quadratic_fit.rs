//! The Wendland-weighted least-squares quadratic patch (METHOD.md §2.6) with its
//! fallback chain quadratic → plane → flat.
//!
//! `f(u,v) = c0 + c1 u + c2 v + c3 u² + c4 uv + c5 v²` is fitted to the point and its
//! neighbours in the point's local frame. `c0` is free: the patch need not pass
//! through the point, as in the paper.

use std::sync::LazyLock;

use glam::Vec3;

use crate::wendland::wendland;
#[cfg(test)]
use pointray_patches::patch_bounds::evaluate;

/// Which model the fit ended with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FitKind {
    /// All six coefficients.
    Quadratic,
    /// `c3 = c4 = c5 = 0`: the quadratic was ill-conditioned or wild.
    Plane,
    /// `f = 0`, the tangent plane itself: even the plane was ill-conditioned or wild.
    Flat,
}

/// A fitted patch: the coefficients in world units of the local frame, and the model used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchFit {
    pub coefficients: [f32; 6],
    pub kind: FitKind,
}

/// A pivot of the LDLᵀ factorisation smaller than this fraction of its diagonal entry
/// means that basis function is (nearly) a combination of the earlier ones: the
/// samples cannot tell the coefficients apart, so the fit falls back.
const RELATIVE_PIVOT_LIMIT: f64 = 1e-6;

/// Rim samples used to judge whether a fit stays within its disk.
const RIM_SAMPLES: usize = 16;

/// Fits the patch to `samples`, each a neighbour in local `(u, v, w)` with its distance
/// `r` to the patch's point. `h` is the Wendland scale, `disk_radius` is `d_i`: a fit
/// whose height anywhere on the disk exceeds `d_i` is judged wild and falls back.
pub fn fit_patch(samples: impl Iterator<Item = (Vec3, f32)>, h: f32, disk_radius: f32) -> PatchFit {
    fit_models(samples, h, disk_radius, &[FitKind::Quadratic, FitKind::Plane])
}

/// The first of `models` whose system is well posed and whose fit stays within the disk.
fn fit_models(
    samples: impl Iterator<Item = (Vec3, f32)>,
    h: f32,
    disk_radius: f32,
    models: &[FitKind],
) -> PatchFit {
    if h.is_nan() || h <= 0.0 {
        return PatchFit { coefficients: [0.0; 6], kind: FitKind::Flat };
    }
    let h = f64::from(h);
    let mut equations = NormalEquations::default();
    for (local, distance) in samples {
        let weight = wendland(f64::from(distance) / h);
        // u and v are scaled by 1/h so that all six basis functions are O(1).
        equations.add(f64::from(local.x) / h, f64::from(local.y) / h, f64::from(local.z), weight);
    }
    let disk = f64::from(disk_radius);
    for &kind in models {
        let unknowns = if kind == FitKind::Quadratic { 6 } else { 3 };
        if let Some(scaled) = equations.solve_leading(unknowns)
            && stays_within_disk(&scaled, disk / h, disk)
        {
            return PatchFit { coefficients: unscale(scaled, h), kind };
        }
    }
    PatchFit { coefficients: [0.0; 6], kind: FitKind::Flat }
}

/// The weighted normal equations `Σ w φ φᵀ a = Σ w φ z` for `φ = (1, s, t, s², st, t²)`.
#[derive(Default)]
struct NormalEquations {
    matrix: [[f64; 6]; 6],
    rhs: [f64; 6],
}

impl NormalEquations {
    fn add(&mut self, s: f64, t: f64, height: f64, weight: f64) {
        let basis = [1.0, s, t, s * s, s * t, t * t];
        for (row, &basis_row) in basis.iter().enumerate() {
            let weighted = weight * basis_row;
            for (entry, &basis_col) in self.matrix[row][..=row].iter_mut().zip(&basis) {
                *entry += weighted * basis_col;
            }
            self.rhs[row] += weighted * height;
        }
    }

    /// Solves the system restricted to the first `n` basis functions by LDLᵀ, or
    /// `None` when a pivot shows the system to be ill-conditioned.
    fn solve_leading(&self, n: usize) -> Option<[f64; 6]> {
        let mut lower = [[0.0f64; 6]; 6];
        let mut diagonal = [0.0f64; 6];
        let scale = self.matrix[0][0];
        for j in 0..n {
            let mut pivot = self.matrix[j][j];
            for k in 0..j {
                pivot -= lower[j][k] * lower[j][k] * diagonal[k];
            }
            let well_posed = pivot > RELATIVE_PIVOT_LIMIT * self.matrix[j][j] && pivot > 1e-12 * scale;
            if !well_posed {
                return None;
            }
            diagonal[j] = pivot;
            for i in j + 1..n {
                let mut entry = self.matrix[i][j];
                for k in 0..j {
                    entry -= lower[i][k] * lower[j][k] * diagonal[k];
                }
                lower[i][j] = entry / pivot;
            }
        }
        let mut solution = [0.0f64; 6];
        for i in 0..n {
            solution[i] = self.rhs[i] - (0..i).map(|k| lower[i][k] * solution[k]).sum::<f64>();
        }
        for i in (0..n).rev() {
            solution[i] =
                solution[i] / diagonal[i] - (i + 1..n).map(|k| lower[k][i] * solution[k]).sum::<f64>();
        }
        solution.iter().all(|c| c.is_finite()).then_some(solution)
    }
}

/// Evaluates the scaled quadratic at scaled `(s, t)`.
fn evaluate_scaled(a: &[f64; 6], s: f64, t: f64) -> f64 {
    a[0] + a[1] * s + a[2] * t + a[3] * s * s + a[4] * s * t + a[5] * t * t
}

/// Whether `|f|` stays within `limit` at the centre and on the rim of the disk of
/// scaled radius `scaled_radius`: a larger height means the fit bends away from its
/// neighbours.
fn stays_within_disk(a: &[f64; 6], scaled_radius: f64, limit: f64) -> bool {
    let rim =
        RIM_DIRECTIONS.iter().map(|&(cos, sin)| evaluate_scaled(a, scaled_radius * cos, scaled_radius * sin));
    std::iter::once(a[0]).chain(rim).all(|height| height.abs() <= limit)
}

/// Unit directions to the rim samples, computed once: the trigonometry would otherwise
/// dominate the cost of a fit.
static RIM_DIRECTIONS: LazyLock<[(f64, f64); RIM_SAMPLES]> = LazyLock::new(|| {
    std::array::from_fn(|i| {
        let angle = std::f64::consts::TAU * i as f64 / RIM_SAMPLES as f64;
        (angle.cos(), angle.sin())
    })
});

/// From coefficients in `(u/h, v/h)` back to coefficients in `(u, v)`.
fn unscale(a: [f64; 6], h: f64) -> [f32; 6] {
    let h2 = h * h;
    [a[0], a[1] / h, a[2] / h, a[3] / h2, a[4] / h2, a[5] / h2].map(|c| c as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring_samples(height: impl Fn(f32, f32) -> f32) -> Vec<(Vec3, f32)> {
        let mut samples = vec![(Vec3::new(0.0, 0.0, height(0.0, 0.0)), 0.0)];
        for i in 0..9 {
            let angle = i as f32 * 0.7;
            let radius = 0.5 + 0.05 * i as f32;
            let (u, v) = (radius * angle.cos(), radius * angle.sin());
            let p = Vec3::new(u, v, height(u, v));
            samples.push((p, p.length()));
        }
        samples
    }

    #[test]
    fn reproduces_a_quadratic_exactly() {
        let truth = [0.01, 0.1, -0.2, 0.3, -0.15, 0.05];
        let samples = ring_samples(|u, v| evaluate(&truth, u, v));
        let fit = fit_patch(samples.into_iter(), 1.1, 1.0);
        assert_eq!(fit.kind, FitKind::Quadratic);
        for (got, want) in fit.coefficients.iter().zip(truth) {
            assert!((got - want).abs() < 1e-5, "{:?} vs {truth:?}", fit.coefficients);
        }
    }

    #[test]
    fn collinear_samples_fall_back_to_a_plane() {
        let samples = (0..10).map(|i| {
            let u = i as f32 * 0.1 - 0.45;
            (Vec3::new(u, 0.0, 0.2 * u), u.abs())
        });
        let fit = fit_patch(samples, 1.1, 1.0);
        assert_eq!(fit.kind, FitKind::Flat, "a line cannot fix c2 either");
        let on_a_cross = (0..10).map(|i| {
            let x = i as f32 * 0.1 - 0.45;
            let p = if i % 2 == 0 { Vec3::new(x, 0.0, 0.2 * x) } else { Vec3::new(0.0, x, 0.0) };
            (p, p.length())
        });
        let fit = fit_patch(on_a_cross, 1.1, 1.0);
        assert_eq!(fit.kind, FitKind::Plane, "a cross cannot fix the uv term");
        assert!((fit.coefficients[1] - 0.2).abs() < 1e-5);
    }

    #[test]
    fn a_wild_quadratic_falls_back() {
        let samples = ring_samples(|u, v| 50.0 * u * v);
        let fit = fit_patch(samples.into_iter(), 1.1, 1.0);
        assert_ne!(fit.kind, FitKind::Quadratic);
        assert_eq!(fit_patch(std::iter::empty(), 0.0, 1.0).kind, FitKind::Flat);
    }
}
