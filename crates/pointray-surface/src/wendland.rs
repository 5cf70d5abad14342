//! The Wendland weight of the MLS fit (METHOD.md §2.6).

/// `θ(r) = (1 - r)⁴ (4r + 1)` for `0 <= r < 1`, else 0: smooth, compactly supported,
/// 1 at the centre.
pub fn wendland(r: f64) -> f64 {
    if !(0.0..1.0).contains(&r) {
        return 0.0;
    }
    let one_minus = 1.0 - r;
    let squared = one_minus * one_minus;
    squared * squared * (4.0 * r + 1.0)
}

#[cfg(test)]
mod tests {
    use super::wendland;

    #[test]
    fn one_at_the_centre_zero_outside_and_decreasing() {
        assert_eq!(wendland(0.0), 1.0);
        assert_eq!(wendland(1.0), 0.0);
        assert_eq!(wendland(1.5), 0.0);
        assert_eq!(wendland(-0.1), 0.0);
        let samples: Vec<f64> = (0..=100).map(|i| wendland(i as f64 / 100.0)).collect();
        assert!(samples.windows(2).all(|w| w[1] < w[0]));
        assert!((wendland(0.5) - 0.1875).abs() < 1e-12);
    }
}
