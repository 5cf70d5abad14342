//! The scene a bare points file gets (`render POINTS`, `view POINTS`): the cloud stood upright,
//! coloured by what it carries, on an optional reflective floor, lit by one directional light
//! (which needs no knowledge of the cloud's size), framed by the default camera.

use std::path::{Path, PathBuf};
use std::str::FromStr;

use glam::DVec3;

use pointray_io::formats::detect::PointFormat;
use pointray_io::formats::{FileFormat, detect_file_format};

use crate::file_camera::FileCamera;
use crate::material_spec::{ColorSource, MaterialSpec};
use crate::object_spec::{ObjectSpec, ShapeSpec};
use crate::scene_file::{CameraSpec, LightSpec, RenderSpec, SceneFile};
use crate::transform_spec::{RotationSpec, TransformSpec};

/// Which of the file's axes points up. The scene is Y-up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UpAxis {
    Y,
    Z,
}

impl UpAxis {
    /// Scans (LAS, LAZ, E57, PCD and raw sweeps) are Z-up by convention; models (PLY, OBJ and
    /// text) are Y-up, like the scene. A file that cannot be read is taken as Y-up: loading
    /// it reports the real problem.
    pub fn conventional(path: &Path) -> Self {
        match detect_file_format(path) {
            Ok(FileFormat::Points(
                PointFormat::Las
                | PointFormat::Laz
                | PointFormat::E57
                | PointFormat::Pcd
                | PointFormat::RawBin,
            )) => UpAxis::Z,
            _ => UpAxis::Y,
        }
    }

    /// A camera placed in the file's coordinates, `up` included, in the scene's. Without `up`
    /// it is the file's up axis, unless the view runs along that axis (from straight above or
    /// below): then the top of the image is the file's north (+Y of a Z-up file, -Z of a
    /// Y-up one, the scene's -Z either way).
    pub fn camera_from_file(self, camera: &FileCamera) -> CameraSpec {
        let FileCamera { position, look_at, up, vfov_degrees } = *camera;
        let up = up.unwrap_or_else(|| self.up_for_view(position, look_at));
        CameraSpec {
            up: self.upright_vector(up).map(|c| c as f32),
            ..CameraSpec::looking(self.upright_vector(position), self.upright_vector(look_at), vfov_degrees)
        }
    }

    fn up_for_view(self, position: [f64; 3], look_at: [f64; 3]) -> [f64; 3] {
        let (axis, north) = match self {
            UpAxis::Y => ([0.0, 1.0, 0.0], [0.0, 0.0, -1.0]),
            UpAxis::Z => ([0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
        };
        let forward = (DVec3::from(look_at) - DVec3::from(position)).normalize_or_zero();
        // Nearly along the axis, the image would turn with the slightest change of the view.
        if forward.cross(DVec3::from(axis)).length() < 1e-3 { north } else { axis }
    }

    /// A position or direction of the file in the scene.
    fn upright_vector(self, file: [f64; 3]) -> [f64; 3] {
        match self {
            UpAxis::Y => file,
            // The quarter turn of `upright`: +Z to +Y.
            UpAxis::Z => [file[0], file[2], -file[1]],
        }
    }

    fn upright(self) -> TransformSpec {
        match self {
            UpAxis::Y => TransformSpec::default(),
            // A quarter turn about X takes +Z to +Y.
            UpAxis::Z => TransformSpec {
                rotate: Some(RotationSpec::EulerDegrees([-90.0, 0.0, 0.0])),
                ..TransformSpec::default()
            },
        }
    }
}

impl FromStr for UpAxis {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text.to_ascii_lowercase().as_str() {
            "y" => Ok(UpAxis::Y),
            "z" => Ok(UpAxis::Z),
            _ => Err(format!("unknown up axis `{text}`; give y or z")),
        }
    }
}

/// Points with no file to go by (from a program's memory) are taken as Y-up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointsScene {
    pub up: UpAxis,
    pub floor: bool,
    pub color_source: ColorSource,
}

impl Default for PointsScene {
    fn default() -> Self {
        Self { up: UpAxis::Y, floor: true, color_source: ColorSource::Auto }
    }
}

impl PointsScene {
    /// The file's conventional up axis, a floor, and colours by what the points carry.
    pub fn conventional(path: &Path) -> Self {
        Self { up: UpAxis::conventional(path), ..Self::default() }
    }

    pub fn scene_file(&self, points: &Path) -> SceneFile {
        let cloud = ObjectSpec {
            name: None,
            transform: self.up.upright(),
            material: MaterialSpec { color_source: Some(self.color_source), ..MaterialSpec::default() },
            shape: ShapeSpec::Points { path: points.to_path_buf(), prep: None, columns: None },
        };
        let floor = ObjectSpec {
            name: None,
            transform: TransformSpec::default(),
            material: MaterialSpec {
                specular: Some(0.0),
                reflectivity: Some(0.3),
                ..MaterialSpec::default()
            },
            shape: ShapeSpec::Ground { auto: true, height: None, size: None },
        };
        SceneFile {
            camera: None,
            lights: vec![LightSpec::Directional {
                direction: [-0.4, -1.0, -0.5],
                color: [1.0; 3],
                intensity: 1.0,
            }],
            background: None,
            objects: if self.floor { vec![cloud, floor] } else { vec![cloud] },
            render: RenderSpec::default(),
            // Relative paths stay relative to the working directory, as the user typed them.
            path: PathBuf::from("(default scene)"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn looking(position: [f64; 3], look_at: [f64; 3]) -> FileCamera {
        FileCamera { position, look_at, up: None, vfov_degrees: None }
    }

    #[test]
    fn a_view_from_straight_above_has_north_at_the_top() {
        let above = looking([10.0, 20.0, 3000.0], [10.0, 20.0, 400.0]);
        let camera = UpAxis::Z.camera_from_file(&above);
        assert_eq!(camera.up, [0.0, 0.0, -1.0], "the file's +Y, in the scene");
        let oblique = UpAxis::Z.camera_from_file(&looking([0.0, -50.0, 30.0], [0.0; 3]));
        assert_eq!(oblique.up, [0.0, 1.0, 0.0], "the file's +Z, in the scene");
        let given = FileCamera { up: Some([1.0, 0.0, 0.0]), vfov_degrees: Some(30.0), ..above };
        let given = UpAxis::Z.camera_from_file(&given);
        assert_eq!((given.up, given.vfov_degrees), ([1.0, 0.0, 0.0], 30.0));
    }

    #[test]
    fn a_given_up_is_stood_upright_with_the_position_and_look_at() {
        let tilted = FileCamera { up: Some([0.0, 1.0, 1.0]), ..looking([1.0, -50.0, 30.0], [2.0, 3.0, 4.0]) };
        let camera = UpAxis::Z.camera_from_file(&tilted);
        assert_eq!(camera.position, [1.0, 30.0, 50.0]);
        assert_eq!(camera.look_at, [2.0, 4.0, -3.0]);
        assert_eq!(camera.up, [0.0, 1.0, -1.0], "the file's +Y+Z, in the scene");
        assert_eq!(UpAxis::Y.camera_from_file(&tilted).up, [0.0, 1.0, 1.0], "a Y-up file is the scene");
    }
}
