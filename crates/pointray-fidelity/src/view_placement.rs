//! From the views asked for to cameras and image sizes.

use glam::Vec3;
use pointray_kernels::Aabb;
use pointray_scene::{Camera, Scene};

use crate::view_directions::view_directions;
use crate::{FidelityError, SensorPose, ViewSpec};

/// A moderate lens for the views that frame the mesh: wide lenses stretch the silhouette
/// pixels that dominate the hole count.
const FRAMING_FOV_DEGREES: f32 = 40.0;
/// Image sides past this are a typing error, not a measurement (a frame of its square
/// holds 48 bytes a pixel per backend).
pub const MAXIMUM_SIZE: u32 = 8192;

/// One placed camera and the image it renders.
#[derive(Clone, Debug, PartialEq)]
pub struct View {
    /// Names the view in reports.
    pub label: String,
    pub camera: Camera,
    pub width: u32,
    pub height: u32,
}

/// What placing a view may need besides the spec.
pub struct ViewSetting<'a> {
    /// The mesh's bounds, which views around it frame.
    pub mesh_bounds: &'a Aabb,
    /// The centre of the points' bounds, which `above` views look down on.
    pub points_centre: Vec3,
    /// The scan's up axis, unit length.
    pub up: Vec3,
    /// The vertical field of view of explicit and `above` views.
    pub fov_degrees: f32,
    /// Images are this wide, and square but for sensor views.
    pub size: u32,
    /// Where the sensor stood, for sensor views.
    pub sensor: Option<&'a SensorPose>,
}

/// Every camera `specs` ask for, in order.
pub fn place_views(specs: &[ViewSpec], setting: &ViewSetting) -> Result<Vec<View>, FidelityError> {
    let mut views = Vec::new();
    for spec in specs {
        spec.validate()?;
        match *spec {
            ViewSpec::Around { count } => {
                views.extend(view_directions(count)?.into_iter().map(|d| framing_view(d, setting)))
            }
            ViewSpec::Direction(direction) => views.push(framing_view(direction, setting)),
            ViewSpec::Explicit { from, at } => views.push(explicit_view(spec, from, at, setting)),
            ViewSpec::Sensor { yaws } => {
                let sensor = setting.sensor.ok_or(FidelityError::NoSensor)?;
                views.extend(crate::sensor_views::sensor_views(sensor, yaws, setting)?);
            }
            ViewSpec::Above { height } => views.push(crate::sensor_views::above_view(height, setting)),
        }
    }
    Ok(views)
}

/// Checks what the setting carries before any view is placed.
pub fn validate_setting(up: Vec3, fov_degrees: f32, size: u32) -> Result<(), FidelityError> {
    if !(up.is_finite() && up.length() > 0.0) {
        return Err(FidelityError::InvalidUp(up));
    }
    if !(fov_degrees.is_finite() && fov_degrees > 0.0 && fov_degrees < 170.0) {
        return Err(FidelityError::InvalidFov(fov_degrees));
    }
    if !(1..=MAXIMUM_SIZE).contains(&size) {
        return Err(FidelityError::ImageSize { size, maximum: MAXIMUM_SIZE });
    }
    Ok(())
}

fn framing_view(direction: Vec3, setting: &ViewSetting) -> View {
    let camera = Scene::framing_camera(setting.mesh_bounds, direction, FRAMING_FOV_DEGREES, 1.0);
    let label = ViewSpec::Direction(direction).to_string();
    View { label, camera, width: setting.size, height: setting.size }
}

fn explicit_view(spec: &ViewSpec, from: Vec3, at: Vec3, setting: &ViewSetting) -> View {
    let camera = Camera {
        position: from,
        look_at: at,
        up: up_across(at - from, setting.up),
        vertical_fov_degrees: setting.fov_degrees,
    };
    View { label: spec.to_string(), camera, width: setting.size, height: setting.size }
}

/// `up`, or where the camera looks along it, the axis of the three that is most across
/// the view: a camera's up must not lie along its line of sight.
pub fn up_across(forward: Vec3, up: Vec3) -> Vec3 {
    let forward = forward.normalize_or_zero();
    if forward.cross(up).length() > 1e-3 * up.length() {
        return up;
    }
    [Vec3::Z, Vec3::Y, Vec3::X]
        .into_iter()
        .min_by(|a, b| forward.dot(*a).abs().total_cmp(&forward.dot(*b).abs()))
        .unwrap_or(Vec3::Y)
}
