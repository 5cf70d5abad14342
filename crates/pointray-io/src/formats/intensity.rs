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
    let (min, max) = finite_range(raw)?;
    if max <= 0.0 && min >= 0.0 {
        return None;
    }
    let (low, scale) = if min < 0.0 { (min, max - min) } else { (0.0, full_scale_covering(max)) };
    Some(raw.iter().map(|&value| scaled(value, low, scale)).collect())
}

fn finite_range(raw: &[f64]) -> Option<(f64, f64)> {
    raw.iter().filter(|value| value.is_finite()).fold(None, |range, &value| match range {
        None => Some((value, value)),
        Some((min, max)) => Some((f64::min(min, value), f64::max(max, value))),
    })
}

fn full_scale_covering(max: f64) -> f64 {
    SENSOR_FULL_SCALES.into_iter().find(|&scale| max <= scale).unwrap_or(max)
}

/// Non-finite values (a sensor's "no return") become 0.
fn scaled(value: f64, low: f64, scale: f64) -> f32 {
    if !value.is_finite() || scale <= 0.0 {
        return 0.0;
    }
    ((value - low) / scale).clamp(0.0, 1.0) as f32
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
