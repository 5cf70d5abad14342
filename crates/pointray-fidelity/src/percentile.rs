//! Order statistics of error samples.

/// The nearest-rank percentile (`fraction` in [0, 1]) of `values`: the smallest value with at
/// least `fraction` of the values at or below it. `None` for no values. Reorders `values`.
pub fn percentile(values: &mut [f32], fraction: f64) -> Option<f32> {
    if values.is_empty() {
        return None;
    }
    let rank = (fraction.clamp(0.0, 1.0) * values.len() as f64).ceil() as usize;
    let index = rank.clamp(1, values.len()) - 1;
    let (_, value, _) = values.select_nth_unstable_by(index, f32::total_cmp);
    Some(*value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_rank_on_one_to_a_hundred() {
        let mut values: Vec<f32> = (1..=100).rev().map(|v| v as f32).collect();
        assert_eq!(percentile(&mut values, 0.99), Some(99.0));
        assert_eq!(percentile(&mut values, 0.95), Some(95.0));
        assert_eq!(percentile(&mut values, 1.0), Some(100.0));
        assert_eq!(percentile(&mut values, 0.0), Some(1.0));
    }

    #[test]
    fn empty_has_no_percentile() {
        assert_eq!(percentile(&mut [], 0.5), None);
    }
}
