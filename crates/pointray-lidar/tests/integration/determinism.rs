//! A seed gives the same scan on any number of threads; another seed gives another one.

use pointray_lidar::{NoProgress, Sensor, SensorPreset, scan};

use crate::common::*;

#[test]
fn a_seed_fixes_noise_and_dropout() {
    let room = room();
    let sensor = Sensor { range_noise: 0.05, dropout: 0.2, ..exact(SensorPreset::Hdl64, 3.0) };
    let stations = [station(0.0, 0.0, 1.7), station(4.0, 1.0, 1.7)];
    let run = |seed| scan(&room, &sensor, &stations, seed, &NoProgress).unwrap().returns;
    let first = run(42);
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    assert_eq!(first, one_thread.install(|| run(42)), "the thread count changed the scan");
    assert_eq!(first, run(42));
    let other = run(43);
    assert_ne!(first.len(), 0);
    assert!(
        first.len() != other.len() || first.iter().zip(&other).any(|(a, b)| a.position != b.position),
        "another seed gave the same scan"
    );
}
