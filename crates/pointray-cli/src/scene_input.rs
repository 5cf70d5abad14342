//! What `render` and `view` take: a scene file, or a bare points file given the default scene,
//! with flags that shape that scene and place the camera.

use std::path::Path;

use clap::Args;
use glam::DVec3;
use pointray_scene::material_spec::ColorSource;
use pointray_scene::{FileCamera, PointsScene, SceneFile, UpAxis};

use crate::columns_arg::ColumnsArg;
use crate::point_arg::parse_finite;

#[derive(Args)]
pub struct SceneInputArgs {
    #[command(flatten)]
    columns: ColumnsArg,
    /// For a points file: which of its axes is up, `y` or `z` (default: `z` for LAS, LAZ, E57,
    /// PCD and .bin sweeps, `y` for PLY, OBJ and text).
    #[arg(long, value_name = "AXIS")]
    up_axis: Option<UpAxis>,
    /// For a points file: stand it on a reflective floor (default true).
    #[arg(long, value_name = "BOOL", action = clap::ArgAction::Set)]
    floor: Option<bool>,
    /// For a points file: `auto` (its RGB where it has colours, else its intensity in grey),
    /// `points`, `intensity`, `height`, `classification` or `fixed`.
    #[arg(long, value_name = "SOURCE")]
    color: Option<ColorSource>,
    /// Put the camera here, `x,y,z`, in the file's coordinates (with `--look-at`).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true, requires = "look_at")]
    look_from: Option<DVec3>,
    /// Where the camera looks, `x,y,z`, in the file's coordinates (with `--look-from`).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true, requires = "look_from")]
    look_at: Option<DVec3>,
    /// The camera's vertical field of view in degrees (with `--look-from`).
    #[arg(long, requires = "look_from")]
    fov: Option<f32>,
    /// Which way is the top of the image, `x,y,z`, in the file's coordinates (with
    /// `--look-from`; default: the file's up axis, or its north for a view from straight above).
    #[arg(long, value_parser = parse_finite, allow_hyphen_values = true, requires = "look_from")]
    up: Option<DVec3>,
}

impl SceneInputArgs {
    /// A `.toml` is a scene; anything else is a points file given the default scene.
    pub fn scene_file(&self, path: &Path) -> anyhow::Result<SceneFile> {
        let is_scene = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml"));
        let (file, up) = if is_scene {
            self.refuse_points_flags(path)?;
            (SceneFile::read(path)?, UpAxis::Y)
        } else {
            let mut look = PointsScene::conventional(path);
            look.up = self.up_axis.unwrap_or(look.up);
            look.floor = self.floor.unwrap_or(look.floor);
            look.color_source = self.color.unwrap_or(look.color_source);
            (look.scene_file(path), look.up)
        };
        let mut file = self.columns.apply_to(file);
        if let (Some(from), Some(at)) = (self.look_from, self.look_at) {
            let camera = FileCamera {
                position: from.to_array(),
                look_at: at.to_array(),
                up: self.up.map(|up| up.to_array()),
                vfov_degrees: self.fov,
            };
            file.camera = Some(up.camera_from_file(&camera));
            // A camera that cannot be is refused now, not after the points are prepped.
            file.recheck()?;
        }
        Ok(file)
    }

    fn refuse_points_flags(&self, scene: &Path) -> anyhow::Result<()> {
        let given = [
            ("--up-axis", self.up_axis.is_some()),
            ("--floor", self.floor.is_some()),
            ("--color", self.color.is_some()),
        ];
        match given.iter().find(|(_, given)| *given) {
            Some((flag, _)) => anyhow::bail!(
                "{}: {flag} shapes the scene of a bare points file; a scene file sets it in the file",
                scene.display()
            ),
            None => Ok(()),
        }
    }
}
