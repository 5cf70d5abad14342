//! Settings out of range are refused with a message that names them; nothing panics.

use glam::DVec3;
use pointray_io::TriangleMesh;
use pointray_lidar::{
    LidarError, LidarScene, NoProgress, Sensor, SensorPose, SensorPreset, Surface, UpAxis, scan,
};

use crate::common::*;

fn refusal(sensor: Sensor, stations: &[SensorPose]) -> String {
    match scan(&room(), &sensor, stations, 1, &NoProgress) {
        Ok(_) => panic!("the scan must be refused"),
        Err(error) => error.to_string(),
    }
}

#[test]
fn sensor_settings_out_of_range() {
    let base = || SensorPreset::Vlp16.sensor();
    let one = [station(0.0, 0.0, 0.0)];
    let cases = [
        (Sensor { azimuth_step_deg: 0.0, ..base() }, "--azimuth-step"),
        (Sensor { azimuth_step_deg: f64::NAN, ..base() }, "--azimuth-step"),
        (Sensor { range_noise: -0.1, ..base() }, "--noise"),
        (Sensor { range_noise: f64::INFINITY, ..base() }, "--noise"),
        (Sensor { dropout: 1.0, ..base() }, "--dropout"),
        (Sensor { dropout: -0.5, ..base() }, "--dropout"),
        (Sensor { min_range: -1.0, ..base() }, "--min-range"),
        (Sensor { min_range: 50.0, max_range: 10.0, ..base() }, "--max-range"),
        (Sensor { max_range: f64::NAN, ..base() }, "--max-range"),
        (Sensor { azimuth_step_deg: 1e-9, ..base() }, "rays"),
        (Sensor { elevations: pointray_lidar::Elevations::Beams(vec![3.0, 1.0]), ..base() }, "rise"),
        (Sensor { elevations: pointray_lidar::Elevations::Beams(vec![]), ..base() }, "no rings"),
    ];
    for (sensor, expected) in cases {
        let message = refusal(sensor, &one);
        assert!(message.contains(expected), "expected `{expected}` in: {message}");
    }
    // The terrestrial grid's rows follow the azimuth step; a tiny step is refused before any
    // row is listed.
    let fine_grid = Sensor { azimuth_step_deg: 1e-7, ..SensorPreset::Terrestrial.sensor() };
    assert!(matches!(scan(&room(), &fine_grid, &one, 1, &NoProgress), Err(LidarError::TooManyRays { .. })));
}

#[test]
fn stations_out_of_range() {
    let sensor = SensorPreset::Vlp16.sensor();
    assert!(refusal(sensor.clone(), &[]).contains("at least one station"));
    let nowhere = SensorPose { position: DVec3::new(0.0, f64::NAN, 0.0), yaw_deg: 0.0 };
    assert!(refusal(sensor.clone(), &[nowhere]).contains("--position"));
    let spinning = SensorPose { position: DVec3::ZERO, yaw_deg: f64::INFINITY };
    assert!(refusal(sensor, &[spinning]).contains("--yaw"));
}

#[test]
fn surfaces_that_cannot_be_scanned() {
    let triangle = TriangleMesh {
        positions: vec![glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y],
        triangles: vec![[0, 1, 2]],
    };
    let too_bright = Surface::new("mirror", triangle.clone(), 1.5);
    let error = LidarScene::from_surfaces(&[too_bright], UpAxis::Z).err().unwrap().to_string();
    assert!(error.contains("mirror") && error.contains("reflectance"), "{error}");
    let dangling = Surface::new("torn", TriangleMesh { triangles: vec![[0, 1, 7]], ..triangle }, 0.5);
    let error = LidarScene::from_surfaces(&[dangling], UpAxis::Z).err().unwrap().to_string();
    assert!(error.contains("torn") && error.contains("triangle 0"), "{error}");
    assert!(matches!(LidarScene::from_surfaces(&[], UpAxis::Z), Err(LidarError::EmptyScene)));
}
