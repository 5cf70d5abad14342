//! Bounds for Monte Carlo renders: the mean of independent per-pixel estimates with its
//! standard error, so that a test's tolerance is computed from the noise it sees rather
//! than guessed.

/// The mean of `count` independent estimates and the standard error of that mean.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    pub mean: f64,
    pub standard_error: f64,
    pub count: usize,
}

/// The mean and standard error of `values` (at least two of them).
pub fn estimate(values: impl IntoIterator<Item = f64>) -> Estimate {
    let values: Vec<f64> = values.into_iter().collect();
    let count = values.len();
    assert!(count >= 2, "an estimate needs at least two values, got {count}");
    let mean = values.iter().sum::<f64>() / count as f64;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (count - 1) as f64;
    Estimate { mean, standard_error: (variance / count as f64).sqrt(), count }
}

impl Estimate {
    /// Panics unless `expected` lies within `sigmas` standard errors of the mean, plus
    /// `slack` for what is not noise (f32 rounding, a known truncation).
    pub fn assert_near(&self, expected: f64, sigmas: f64, slack: f64, what: &str) {
        let bound = sigmas * self.standard_error + slack;
        assert!(
            (self.mean - expected).abs() <= bound,
            "{what}: mean {:.5} of {} estimates, expected {expected:.5} within {bound:.5} \
             ({sigmas} standard errors of {:.5} plus {slack})",
            self.mean,
            self.count,
            self.standard_error
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_standard_error_of_known_values() {
        let e = estimate([1.0, 3.0, 1.0, 3.0]);
        assert_eq!(e.mean, 2.0);
        // Sample variance 4/3, over 4 values.
        assert!((e.standard_error - (4.0f64 / 3.0 / 4.0).sqrt()).abs() < 1e-12);
        e.assert_near(2.5, 1.0, 0.0, "within one standard error");
    }

    #[test]
    #[should_panic(expected = "expected 3.00000")]
    fn a_mean_beyond_the_bound_fails() {
        estimate([1.0, 1.1, 0.9, 1.0]).assert_near(3.0, 5.0, 0.0, "far off");
    }
}
