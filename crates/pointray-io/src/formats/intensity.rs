//! Scaling raw sensor intensities into [0, 1].
//!
//! Scanners store intensity in whatever range their hardware produces (8, 12 or 16 bit
//! integers, or floats), and most file formats do not say which. Dividing everything by
//! 65535 would turn an 8-bit sensor's values into near-black, so the full scale is the
//! smallest common sensor range that covers the values actually present.

/// Full-scale ranges of common sensors, smallest first.
const SENSOR_FULL_SCALES: [f64; 4] = [1.0, 255.0, 4095.0, 65535.0];

/// Normalises raw intensities to [0, 1]. Returns `None` when there is nothing to
/// normalise: no values, or every value zero (the file reserves the field but the
/// sensor never filled it).
pub(crate) fn normalise_intensities(raw: &[f64]) -> Option<Vec<f32>> {
    let mut range = IntensityRange::default();
    raw.iter().for_each(|&value| range.include(value));
    let scale = range.scale()?;
    Some(raw.iter().map(|&value| scale.apply(value)).collect())
}

/// The finite raw intensities seen so far: the whole file's range sets the scale, even when
/// it is read in chunks.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct IntensityRange {
    range: Option<(f64, f64)>,
}

impl IntensityRange {
    pub(crate) fn include(&mut self, value: f64) {
        if value.is_finite() {
            let (min, max) = self.range.unwrap_or((value, value));
            self.range = Some((min.min(value), max.max(value)));
        }
    }

    /// The smallest and largest value seen, if any.
    pub(crate) fn bounds(&self) -> Option<(f64, f64)> {
        self.range
    }

    /// The scale onto [0, 1], or `None` when every value was zero or there were none.
    pub(crate) fn scale(&self) -> Option<IntensityScale> {
        let (min, max) = self.range?;
        if max <= 0.0 && min >= 0.0 {
            return None;
        }
        let (low, scale) = if min < 0.0 { (min, max - min) } else { (0.0, full_scale_covering(max)) };
        Some(IntensityScale { low, scale })
    }
}

/// Raw intensity `low` maps to 0, `low + scale` to 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct IntensityScale {
    low: f64,
    scale: f64,
}

impl IntensityScale {
    /// Non-finite values (a sensor's "no return") become 0.
    pub(crate) fn apply(&self, value: f64) -> f32 {
        if !value.is_finite() || self.scale <= 0.0 {
            return 0.0;
        }
        ((value - self.low) / self.scale).clamp(0.0, 1.0) as f32
    }
}

fn full_scale_covering(max: f64) -> f64 {
    SENSOR_FULL_SCALES.into_iter().find(|&scale| max <= scale).unwrap_or(max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eight_bit_values_use_the_eight_bit_scale() {
        let normalised = normalise_intensities(&[0.0, 51.0, 255.0]).unwrap();
        assert_eq!(normalised, vec![0.0, 0.2, 1.0]);
    }

    #[test]
    fn sixteen_bit_values_use_the_sixteen_bit_scale() {
        let normalised = normalise_intensities(&[65535.0, 5000.0]).unwrap();
        assert_eq!(normalised[0], 1.0);
        assert!((normalised[1] - 5000.0 / 65535.0).abs() < 1e-6);
    }

    #[test]
    fn unit_floats_are_kept() {
        assert_eq!(normalise_intensities(&[0.25, 0.5]).unwrap(), vec![0.25, 0.5]);
    }

    #[test]
    fn values_beyond_sixteen_bits_scale_by_their_maximum() {
        assert_eq!(normalise_intensities(&[100_000.0, 50_000.0]).unwrap(), vec![1.0, 0.5]);
    }

    #[test]
    fn negative_values_are_shifted_to_zero() {
        assert_eq!(normalise_intensities(&[-10.0, 0.0, 10.0]).unwrap(), vec![0.0, 0.5, 1.0]);
    }

    #[test]
    fn all_zero_or_empty_means_no_intensity() {
        assert_eq!(normalise_intensities(&[0.0, 0.0]), None);
        assert_eq!(normalise_intensities(&[]), None);
    }
}
