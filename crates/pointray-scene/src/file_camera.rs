//! A camera placed in a points file's coordinates, as `render --look-from` and Python's
//! `camera` give it, before the default scene stands it upright with the cloud
//! (`UpAxis::camera_from_file`).

use serde::Deserialize;

/// The scene file's camera table, in the points file's coordinates. `up` and `vfov_degrees`
/// stay `None` when not given, so that the view picks the top of the image (the file's up
/// axis, or its north from straight above) rather than the scene's +Y.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FileCamera {
    pub position: [f64; 3],
    pub look_at: [f64; 3],
    pub up: Option<[f64; 3]>,
    pub vfov_degrees: Option<f32>,
}
