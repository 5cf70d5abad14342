//! How far a return may lie from the surface along its own ray and still agree with it.

use serde::Serialize;

use crate::FidelityError;

/// The tolerance of one return: the largest of an absolute term, a fraction of its range and
/// a multiple of the local point spacing.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RangeTolerance {
    /// In the cloud's units (metres for LiDAR): a few times the range noise of automotive
    /// sensors (1 to 3 cm).
    pub absolute: f64,
    /// Beam divergence and grazing incidence: where a ray meets the ground at a shallow
    /// angle, a surface a centimetre high moves the hit along the ray by the range over the
    /// sensor's height times that.
    pub range_fraction: f64,
    /// Between returns the surface is a fit, not a measurement: allow for it over the
    /// distance to the `SPACING_NEIGHBOR`th nearest other return.
    pub spacing_multiple: f64,
}

/// Which neighbour's distance is the local spacing: along a scan line the 4th nearest return
/// lies two samples away on either side, on a scanner's grid across the diagonal.
pub const SPACING_NEIGHBOR: usize = 4;

impl Default for RangeTolerance {
    fn default() -> Self {
        Self { absolute: 0.05, range_fraction: 0.01, spacing_multiple: 1.0 }
    }
}

impl RangeTolerance {
    pub fn validate(&self) -> Result<(), FidelityError> {
        let terms = [self.absolute, self.range_fraction, self.spacing_multiple];
        if terms.iter().any(|t| !(t.is_finite() && *t >= 0.0)) || terms.iter().all(|t| *t == 0.0) {
            return Err(FidelityError::InvalidTolerance(*self));
        }
        Ok(())
    }

    /// The tolerance of a return at `range` whose local spacing is `spacing`.
    pub fn at(&self, range: f64, spacing: f64) -> f64 {
        self.absolute.max(self.range_fraction * range).max(self.spacing_multiple * spacing)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_largest_term_wins() {
        let tolerance = RangeTolerance::default();
        assert_eq!(tolerance.at(1.0, 0.01), 0.05);
        assert_eq!(tolerance.at(20.0, 0.1), 0.2);
        assert_eq!(tolerance.at(20.0, 0.3), 0.3);
    }

    #[test]
    fn negative_non_finite_or_all_zero_terms_are_errors() {
        let bad = [
            RangeTolerance { absolute: -0.1, ..RangeTolerance::default() },
            RangeTolerance { range_fraction: f64::NAN, ..RangeTolerance::default() },
            RangeTolerance { absolute: 0.0, range_fraction: 0.0, spacing_multiple: 0.0 },
        ];
        for tolerance in bad {
            assert!(tolerance.validate().is_err(), "{tolerance:?}");
        }
        assert!(RangeTolerance { absolute: 0.0, ..RangeTolerance::default() }.validate().is_ok());
    }
}
