//! A terrestrial scanner's stations merge into one cloud, each point keeping its own origin.

use pointray_lidar::{NoProgress, SensorPreset, scan, to_point_cloud};

use crate::common::*;

#[test]
fn stations_merge_with_per_point_origins() {
    let room = room();
    let sensor = exact(SensorPreset::Terrestrial, 10.0);
    // Rows from −60° up to 80°, columns every 10°.
    let elevations = sensor.elevations_deg();
    assert_eq!(elevations.len(), 15);
    assert_eq!(sensor.columns(), 36);
    let stations = [station(-8.0, 0.0, 1.5), station(9.0, 4.0, 1.5)];
    let scanned = scan(&room, &sensor, &stations, 1, &NoProgress).unwrap();
    let per_station = elevations.len() * 36;
    assert_eq!(scanned.returns.len(), 2 * per_station, "a closed room returns every ray");
    let cloud = to_point_cloud(&scanned.returns);
    for (index, r) in scanned.returns.iter().enumerate() {
        let station = &stations[index / per_station];
        assert_eq!(r.sensor, station.position);
        assert_eq!(cloud.sensor_of(index), Some(station.position));
        assert!(distance_to_room(r.position) < 1e-3, "{} is not on the room's walls", r.position);
        let elevation = ((r.position - r.sensor).normalize().z).asin().to_degrees();
        assert!((elevation - elevations[usize::from(r.ring)]).abs() < 0.01);
        let sweep = (index / per_station) as f64 * sensor.sweep_seconds;
        assert!((sweep..sweep + sensor.sweep_seconds).contains(&f64::from(r.time)));
    }
    assert_eq!(cloud.rings.as_ref().map(Vec::len), Some(cloud.len()));
}
