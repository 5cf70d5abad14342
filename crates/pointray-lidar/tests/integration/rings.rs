//! Each return's ring, elevation, azimuth and time match the preset that fired it.

use std::f64::consts::TAU;

use pointray_lidar::{NoProgress, SensorPose, SensorPreset, scan};

use crate::common::*;

#[test]
fn published_angle_tables() {
    let angles = |preset: SensorPreset| preset.sensor().elevations_deg();
    let hdl64 = angles(SensorPreset::Hdl64);
    assert_eq!(hdl64.len(), 64);
    assert!((hdl64[0] + 24.333).abs() < 1e-3 && (hdl64[63] - 2.0).abs() < 1e-12);
    assert!(hdl64[..32].windows(2).all(|p| (p[1] - p[0] - 0.5).abs() < 1e-9), "lower block: 1/2°");
    assert!(hdl64[32..].windows(2).all(|p| (p[1] - p[0] - 1.0 / 3.0).abs() < 1e-9), "upper block: 1/3°");
    assert!((hdl64[31] + 8.833).abs() < 1e-3 && (hdl64[32] + 8.333).abs() < 1e-3);

    let hdl32: Vec<f64> = angles(SensorPreset::Hdl32).iter().map(|a| (a * 100.0).round() / 100.0).collect();
    let published = [
        -30.67, -29.33, -28.0, -26.67, -25.33, -24.0, -22.67, -21.33, -20.0, -18.67, -17.33, -16.0, -14.67,
        -13.33, -12.0, -10.67, -9.33, -8.0, -6.67, -5.33, -4.0, -2.67, -1.33, 0.0, 1.33, 2.67, 4.0, 5.33,
        6.67, 8.0, 9.33, 10.67,
    ];
    assert_eq!(hdl32, published);
    let vlp16: Vec<f64> = (0..16).map(|i| -15.0 + 2.0 * i as f64).collect();
    assert_eq!(angles(SensorPreset::Vlp16), vlp16);
    let os128 = angles(SensorPreset::Os128);
    assert_eq!(os128.len(), 128);
    assert!((os128[0] + 22.5).abs() < 1e-12 && (os128[127] - 22.5).abs() < 1e-12);
}

#[test]
fn every_ray_of_each_preset_returns_at_its_ring_elevation() {
    let room = room();
    for preset in [SensorPreset::Hdl64, SensorPreset::Hdl32, SensorPreset::Vlp16, SensorPreset::Os128] {
        let sensor = exact(preset, 30.0);
        let yaw = 30.0;
        let stations = [SensorPose { position: glam::DVec3::new(1.0, -2.0, 1.5), yaw_deg: yaw }];
        let scanned = scan(&room, &sensor, &stations, 1, &NoProgress).unwrap();
        let elevations = sensor.elevations_deg();
        assert_eq!(
            scanned.returns.len(),
            elevations.len() * 12,
            "{preset:?}: one return per ray in a closed room"
        );
        for (index, r) in scanned.returns.iter().enumerate() {
            let direction = (r.position - r.sensor).normalize();
            let elevation = direction.z.asin().to_degrees();
            let expected = elevations[usize::from(r.ring)];
            assert!(
                (elevation - expected).abs() < 0.01,
                "{preset:?} ring {}: {elevation}° vs {expected}°",
                r.ring
            );
            assert_eq!(usize::from(r.ring), index % elevations.len(), "{preset:?}: rings in firing order");
            let heading = direction.y.atan2(direction.x) - yaw.to_radians();
            let azimuth = heading.rem_euclid(TAU);
            let wrapped = (azimuth - f64::from(r.azimuth)).abs();
            assert!(wrapped.min(TAU - wrapped) < 1e-4, "{preset:?}: azimuth {} vs {azimuth}", r.azimuth);
            let time = f64::from(r.azimuth) / TAU * sensor.sweep_seconds;
            assert!((f64::from(r.time) - time).abs() < 1e-6);
        }
    }
}
