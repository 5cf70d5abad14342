//! Order statistics of frame times.

use std::time::Duration;

/// The `q`-quantile (0..=1) of `times` by the nearest-rank method; zero for no times.
pub fn quantile(times: &[Duration], q: f64) -> Duration {
    if times.is_empty() {
        return Duration::ZERO;
    }
    let mut sorted = times.to_vec();
    sorted.sort_unstable();
    let rank = (q.clamp(0.0, 1.0) * sorted.len() as f64).ceil() as usize;
    sorted[rank.saturating_sub(1).min(sorted.len() - 1)]
}

pub fn median(times: &[Duration]) -> Duration {
    quantile(times, 0.5)
}

pub fn p90(times: &[Duration]) -> Duration {
    quantile(times, 0.9)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ms(values: &[u64]) -> Vec<Duration> {
        values.iter().map(|&v| Duration::from_millis(v)).collect()
    }

    #[test]
    fn median_and_p90_by_nearest_rank() {
        let times = ms(&[10, 1, 9, 2, 8, 3, 7, 4, 6, 5]);
        assert_eq!(median(&times), Duration::from_millis(5));
        assert_eq!(p90(&times), Duration::from_millis(9));
        assert_eq!(median(&ms(&[7])), Duration::from_millis(7));
        assert_eq!(median(&[]), Duration::ZERO);
    }
}
