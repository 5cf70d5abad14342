//! How closely two casters agree on the same rays (the GPU's against the CPU's): the share
//! of rays both see hit or both see miss, and of those that hit in both, the share whose
//! ranges lie within a tolerance and the largest difference.

use serde::Serialize;

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CasterAgreement {
    pub rays: usize,
    /// Rays that one caster sees hit and the other miss.
    pub hit_or_miss_differs: usize,
    /// Rays that hit in both with ranges further apart than `tolerance`.
    pub range_differs: usize,
    pub tolerance: f64,
    /// The share of rays with the same hit or miss and, where they hit, ranges within
    /// `tolerance`.
    pub agreeing_fraction: f64,
    /// The largest range difference of rays that hit in both.
    pub largest_range_difference: f64,
}

impl CasterAgreement {
    /// `ours` against `reference`, ray by ray.
    pub fn of(ours: &[Option<f64>], reference: &[Option<f64>], tolerance: f64) -> Self {
        let mut agreement = Self {
            rays: ours.len(),
            hit_or_miss_differs: 0,
            range_differs: 0,
            tolerance,
            agreeing_fraction: 1.0,
            largest_range_difference: 0.0,
        };
        for (a, b) in ours.iter().zip(reference) {
            match (a, b) {
                (Some(a), Some(b)) => {
                    let difference = (a - b).abs();
                    agreement.largest_range_difference = agreement.largest_range_difference.max(difference);
                    agreement.range_differs += usize::from(difference > tolerance);
                }
                (None, None) => {}
                _ => agreement.hit_or_miss_differs += 1,
            }
        }
        agreement.hit_or_miss_differs += ours.len().abs_diff(reference.len());
        let differing = agreement.hit_or_miss_differs + agreement.range_differs;
        let rays = ours.len().max(reference.len());
        if rays > 0 {
            agreement.agreeing_fraction = 1.0 - differing as f64 / rays as f64;
        }
        agreement
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_misses_and_ranges_are_told_apart() {
        let ours = [Some(1.0), Some(2.0), None, None, Some(5.0)];
        let reference = [Some(1.0005), Some(2.5), None, Some(4.0), Some(5.0)];
        let agreement = CasterAgreement::of(&ours, &reference, 0.001);
        assert_eq!((agreement.hit_or_miss_differs, agreement.range_differs), (1, 1));
        assert!((agreement.agreeing_fraction - 0.6).abs() < 1e-12);
        assert!((agreement.largest_range_difference - 0.5).abs() < 1e-12);
        let longer = CasterAgreement::of(&ours, &reference[..4], 0.001);
        assert_eq!(longer.hit_or_miss_differs, 2, "a ray one list lacks differs");
    }
}
