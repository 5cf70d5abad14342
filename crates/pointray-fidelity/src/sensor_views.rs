//! The scan's own views: from the sensor around the horizon, and from above.
//!
//! The sensor's frame follows the automotive convention (KITTI, nuScenes, our `scan` output):
//! yaw 0 looks along +x, or +y when the up axis is x; yaws turn counter-clockwise seen
//! from above.

use glam::Vec3;
use pointray_scene::Camera;

use crate::view_placement::{View, ViewSetting, up_across};
use crate::{FidelityError, SensorPose};

/// Pinhole images cannot take in a whole hemisphere; a scanner's band beyond this is cut
/// to the middle of its elevations.
const MAXIMUM_BAND_DEGREES: f32 = 120.0;

/// `yaws` cameras at the sensor, each turned a further `360° / yaws`, each exactly that wide
/// and as tall as the elevations the returns span: the horizon without overlap, and none of
/// the sky or ground the beams never reached.
pub fn sensor_views(
    sensor: &SensorPose,
    yaws: u32,
    setting: &ViewSetting,
) -> Result<Vec<View>, FidelityError> {
    let [low, high] = sensor.elevation_degrees;
    let band = (high - low).min(MAXIMUM_BAND_DEGREES);
    if band.is_nan() || band <= 0.0 {
        return Err(FidelityError::NoElevationBand);
    }
    let tilt = (0.5 * (low + high)).to_radians();
    let half_width = (180.0 / yaws as f32).to_radians();
    let height = (setting.size as f32 * (0.5 * band).to_radians().tan() / half_width.tan()).round().max(1.0);
    // From the rounded height, so that the horizontal field stays exactly one yaw wide.
    let vertical_fov = 2.0 * (half_width.tan() * height / setting.size as f32).atan();
    let (forward, left) = horizon_axes(setting.up);
    let views = (0..yaws)
        .map(|k| {
            let yaw = (k as f32 * 360.0 / yaws as f32).to_radians();
            let across = forward * yaw.cos() + left * yaw.sin();
            let direction = across * tilt.cos() + setting.up * tilt.sin();
            let camera = Camera {
                position: sensor.position,
                look_at: sensor.position + direction,
                up: up_across(direction, setting.up),
                vertical_fov_degrees: vertical_fov.to_degrees(),
            };
            let label = format!("sensor yaw {:+.0}°", yaw.to_degrees());
            View { label, camera, width: setting.size, height: height as u32 }
        })
        .collect();
    Ok(views)
}

/// A square view straight down from `height` above the points' centre, the sensor's forward
/// axis at the top of the image.
pub fn above_view(height: f32, setting: &ViewSetting) -> View {
    let (forward, _) = horizon_axes(setting.up);
    let camera = Camera {
        position: setting.points_centre + setting.up * height,
        look_at: setting.points_centre,
        up: forward,
        vertical_fov_degrees: setting.fov_degrees,
    };
    View { label: format!("above {height}"), camera, width: setting.size, height: setting.size }
}

/// The sensor's forward and left axes, across the unit `up`.
pub fn horizon_axes(up: Vec3) -> (Vec3, Vec3) {
    let reject = |axis: Vec3| (axis - up * axis.dot(up)).try_normalize();
    let forward = reject(Vec3::X)
        .filter(|_| up.dot(Vec3::X).abs() < 0.9)
        .or_else(|| reject(Vec3::Y))
        .unwrap_or(Vec3::Y);
    (forward, up.cross(forward))
}
