//! Unevenly sampled stand-ins for real scans, for measuring what non-uniform density does to
//! the patches against the mesh's ground truth: uniform samples thinned either by
//! a density gradient across the model or into scan lines.

use glam::DVec3;
use pointray_io::{PointCloud, TriangleMesh};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::sampling::sample_mesh;

/// How the samples are thinned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unevenness {
    /// The density falls by `ratio` from the model's -x end to its +x end, exponentially
    /// in x, as a scan's density falls with range.
    Gradient { ratio: f64 },
    /// Strips across x, as the lines of an airborne or driving scan: each `spacing` of
    /// the model's x extent keeps only its first `duty` fraction, so points crowd along
    /// the lines and gaps of `(1 - duty) * spacing` lie between them.
    ScanLines { lines: u32, duty: f64 },
}

/// About `count` points on `mesh`, thinned as `unevenness` says; the same for the same `seed`.
pub fn sample_mesh_unevenly(
    mesh: &TriangleMesh,
    count: usize,
    seed: u64,
    unevenness: Unevenness,
) -> PointCloud {
    let candidates =
        sample_mesh(mesh, (count as f64 / kept_fraction(unevenness)).ceil() as usize, seed, false);
    let (min_x, max_x) = candidates
        .positions
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p.x), hi.max(p.x)));
    let extent = (max_x - min_x).max(f64::MIN_POSITIVE);
    // A second stream, so that the thinning does not reuse the sampler's random numbers.
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x005e_ed0f_7417);
    let positions: Vec<DVec3> = candidates
        .positions
        .into_iter()
        .filter(|p| keep(unevenness, (p.x - min_x) / extent, rng.random::<f64>()))
        .collect();
    PointCloud::from_positions(positions)
}

/// Whether a candidate at `t` of the x extent survives, given a uniform `draw` in [0, 1).
fn keep(unevenness: Unevenness, t: f64, draw: f64) -> bool {
    match unevenness {
        Unevenness::Gradient { ratio } => draw < ratio.powf(-t),
        Unevenness::ScanLines { lines, duty } => (t * f64::from(lines)).fract() < duty,
    }
}

/// The share of uniform candidates that survive on a model spread evenly along x.
fn kept_fraction(unevenness: Unevenness) -> f64 {
    match unevenness {
        Unevenness::Gradient { ratio } if ratio > 1.0 => (1.0 - 1.0 / ratio) / ratio.ln(),
        Unevenness::Gradient { .. } => 1.0,
        Unevenness::ScanLines { duty, .. } => duty.clamp(1e-3, 1.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square in z = 0.
    fn square() -> TriangleMesh {
        let positions = vec![glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::new(1.0, 1.0, 0.0), glam::Vec3::Y];
        TriangleMesh { positions, triangles: vec![[0, 1, 2], [0, 2, 3]] }
    }

    #[test]
    fn a_tenfold_gradient_thins_the_far_end_tenfold() {
        let cloud = sample_mesh_unevenly(&square(), 40_000, 7, Unevenness::Gradient { ratio: 10.0 });
        let near = cloud.positions.iter().filter(|p| p.x < 0.1).count() as f64;
        let far = cloud.positions.iter().filter(|p| p.x > 0.9).count() as f64;
        assert!((7.0..14.0).contains(&(near / far)), "near {near}, far {far}");
        assert!((36_000..44_000).contains(&cloud.len()), "{}", cloud.len());
    }

    #[test]
    fn scan_lines_leave_empty_gaps() {
        let cloud =
            sample_mesh_unevenly(&square(), 10_000, 7, Unevenness::ScanLines { lines: 10, duty: 0.25 });
        // The lines follow the samples' own x extent, a hair inside [0, 1].
        let in_gap = |x: f64| (0.26..0.99).contains(&(x * 10.0).fract());
        assert!(!cloud.positions.iter().any(|p| in_gap(p.x)), "a point fell in a gap");
        assert!((9_000..11_000).contains(&cloud.len()), "{}", cloud.len());
    }
}
