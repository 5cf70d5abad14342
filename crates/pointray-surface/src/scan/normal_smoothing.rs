//! Normals of a scan's planes, averaged over the neighbours that agree on them. Each return's
//! plane fits a few returns a few centimetres apart, so the range noise tilts it by several
//! degrees (a near façade seen by a 128-beam sensor with 3 cm of noise is mottled). The planes
//! of the returns around it fit overlapping but different returns: their mean tilts less.

use glam::Vec3;

use crate::scan::neighborhood::ScanNeighborhood;

/// Only neighbours whose normals lie within this angle (10°) of the return's own are averaged:
/// the noise tilts planes by less, while across a crease or a step normals differ by more.
const SMOOTHING_COSINE: f32 = 0.985;

/// A return whose mean turns further than this (5°) from its own normal keeps its own: it
/// lies where surfaces meet, and the mean there is neither. Measured on the street sweeps of
/// bench/FIDELITY.md: a 10° limit let the holes from the sensor rise by up to 0.07 points of
/// a percent, 5° by up to 0.03.
const MAX_SMOOTHING_COSINE: f32 = 0.996;

/// The mean of a return's fitted normal (`own.normal`) and those of its neighbourhood's
/// members that agree with it (`fitted_normals[j]` for each member `j`), sign-aligned with its
/// own; its own normal where that mean turns too far.
pub(crate) fn smoothed_normal(own: &ScanNeighborhood, fitted_normals: &[Vec3]) -> Vec3 {
    let normal = own.normal;
    let agreeing = own.members.iter().map(|&j| fitted_normals[j as usize]).filter_map(|other| {
        let cosine = other.dot(normal);
        (cosine.abs() >= SMOOTHING_COSINE).then(|| other * cosine.signum())
    });
    let mean = agreeing.fold(normal, |sum, other| sum + other).normalize_or(normal);
    if mean.dot(normal) >= MAX_SMOOTHING_COSINE { mean } else { normal }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn neighborhood(normal: Vec3, members: Vec<u32>) -> ScanNeighborhood {
        ScanNeighborhood { members, normal: normal.normalize(), crosses_lines: true }
    }

    /// Each neighbourhood's smoothed normal.
    fn smoothed_normals(neighborhoods: &[ScanNeighborhood]) -> Vec<Vec3> {
        let fitted: Vec<Vec3> = neighborhoods.iter().map(|n| n.normal).collect();
        neighborhoods.iter().map(|n| smoothed_normal(n, &fitted)).collect()
    }

    #[test]
    fn tilts_of_either_sign_average_out() {
        let tilted = |x: f32| Vec3::new(x, 0.0, 1.0);
        let hoods = vec![
            neighborhood(tilted(0.05), vec![1, 2, 3]),
            neighborhood(tilted(-0.05), vec![0]),
            neighborhood(-tilted(-0.03), vec![0]),
            neighborhood(tilted(0.03), vec![0]),
        ];
        let smoothed = smoothed_normals(&hoods);
        assert!(smoothed[0].dot(Vec3::Z) > hoods[0].normal.dot(Vec3::Z), "{}", smoothed[0]);
        assert!(smoothed[0].z > 0.0, "keeps its own sign: {}", smoothed[0]);
    }

    #[test]
    fn a_neighbour_across_a_crease_is_left_out() {
        let hoods = vec![neighborhood(Vec3::Z, vec![1]), neighborhood(Vec3::new(1.0, 0.0, 1.0), vec![0])];
        for (smoothed, hood) in smoothed_normals(&hoods).iter().zip(&hoods) {
            assert!(smoothed.dot(hood.normal) > 1.0 - 1e-6, "{smoothed} against {}", hood.normal);
        }
    }

    #[test]
    fn a_mean_that_turns_too_far_is_not_taken() {
        let own = Vec3::new(0.0, 0.0, 1.0);
        let others = Vec3::new(0.17, 0.0, 1.0); // 9.6° away: each agrees, their mean turns past 5°
        let hoods = vec![
            neighborhood(own, vec![1, 2, 3]),
            neighborhood(others, vec![]),
            neighborhood(others, vec![]),
            neighborhood(others, vec![]),
        ];
        assert_eq!(smoothed_normals(&hoods)[0], own);
    }
}
