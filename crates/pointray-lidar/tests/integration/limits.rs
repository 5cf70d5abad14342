//! Dropout thins returns at its probability; no return lies outside the range limits.

use pointray_lidar::{NoProgress, Sensor, SensorPreset, scan};

use crate::common::*;

#[test]
fn dropout_loses_returns_at_its_probability() {
    let room = room();
    let origin = [station(0.0, 0.0, 1.0)];
    let full = scan(&room, &exact(SensorPreset::Vlp16, 1.0), &origin, 5, &NoProgress).unwrap();
    assert_eq!(full.stats.returns, full.stats.rays, "a closed room returns every ray");
    for dropout in [0.1, 0.5] {
        let sensor = Sensor { dropout, ..exact(SensorPreset::Vlp16, 1.0) };
        let thinned = scan(&room, &sensor, &origin, 5, &NoProgress).unwrap();
        let stats = thinned.stats;
        assert_eq!(stats.returns + stats.dropped, stats.rays);
        let lost = stats.dropped as f64 / stats.rays as f64;
        // 5,760 rays: three standard deviations are under 0.02.
        assert!((lost - dropout).abs() < 0.02, "dropout {dropout}: lost {lost}");
        // What survives is what the full scan saw, not something else.
        assert!(thinned.returns.iter().all(|r| full.returns.contains(r)));
    }
}

#[test]
fn returns_stay_within_the_minimum_and_maximum_range() {
    let room = room();
    let (min_range, max_range) = (6.0, 12.0);
    for range_noise in [0.0, 0.3] {
        let sensor = Sensor { min_range, max_range, range_noise, ..exact(SensorPreset::Hdl32, 2.0) };
        let scanned = scan(&room, &sensor, &[station(0.0, 0.0, 1.0)], 9, &NoProgress).unwrap();
        let stats = scanned.stats;
        assert!(stats.returns > 0 && stats.misses > 0 && stats.out_of_range > 0, "{stats:?}");
        assert_eq!(stats.returns + stats.misses + stats.out_of_range, stats.rays);
        for r in &scanned.returns {
            let range = r.position.distance(r.sensor);
            assert!((min_range..=max_range).contains(&range), "range {range} with noise {range_noise}");
        }
    }
}
