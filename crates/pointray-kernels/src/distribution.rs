//! Piecewise-constant distributions over intervals, as the lights drawn from tables use them
//! (the environment map's rows and texels, the emissive triangles): built from weights, and
//! searched for the interval a uniform number falls in. Their GLSL twins sit in
//! `environment_map.glsl` and `emissive_triangles.glsl`, each reading its own buffer.

/// The normalised running sums of `weights`, from 0 to exactly 1 (`weights.len() + 1`
/// values); even steps where every weight is zero, which sampling never picks (an outer
/// distribution gives them no mass).
pub(crate) fn cumulative(weights: &[f64]) -> Vec<f32> {
    let total: f64 = weights.iter().sum();
    let count = weights.len() as f64;
    let mut sum = 0.0;
    let mut values = vec![0.0];
    for (i, weight) in weights.iter().enumerate() {
        sum += weight;
        values.push(if total > 0.0 { (sum / total) as f32 } else { (i + 1) as f32 / count as f32 });
    }
    *values.last_mut().expect("one value at least") = 1.0;
    values
}

/// The last interval of `values` (`values.len() - 1` of them) whose start lies at or below
/// `u`, and where in it `u` falls, in [0, 1].
pub(crate) fn sample_cumulative(values: &[f32], u: f32) -> (u32, f32) {
    let (mut low, mut high) = (0, values.len() - 1);
    while high - low > 1 {
        let middle = (low + high) / 2;
        if values[middle] <= u {
            low = middle;
        } else {
            high = middle;
        }
    }
    let width = values[low + 1] - values[low];
    let fraction = if width > 0.0 { ((u - values[low]) / width).clamp(0.0, 1.0) } else { 0.0 };
    (low as u32, fraction)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_are_found_and_empty_ones_skipped() {
        let values = cumulative(&[1.0, 0.0, 3.0]);
        assert_eq!(values, vec![0.0, 0.25, 0.25, 1.0]);
        assert_eq!(sample_cumulative(&values, 0.125), (0, 0.5));
        assert_eq!(sample_cumulative(&values, 0.25), (2, 0.0));
        assert_eq!(sample_cumulative(&values, 0.625), (2, 0.5));
        assert_eq!(cumulative(&[0.0, 0.0]), vec![0.0, 0.5, 1.0]);
    }
}
