//! The scene file (TOML). Unknown keys are errors. Relative paths are relative to the scene
//! file's folder.
//!
//! ```toml
//! [camera]                  # optional: without it, the objects are framed automatically
//! position = [0.0, 0.15, 0.45]
//! look_at = [0.0, 0.1, 0.0]
//! up = [0.0, 1.0, 0.0]      # default
//! vfov_degrees = 40.0       # default 45
//!
//! [[lights]]
//! type = "point"            # or "directional" with `direction` (the way the light travels),
//! position = [1.0, 2.0, 1.0] # "sphere" with `center` and `radius`, or "quad" with `corner`,
//! color = [1.0, 1.0, 1.0]   # `edge_u` and `edge_v` (emitting toward edge_u x edge_v);
//! intensity = 1.0           # default white, 1 (see `light.rs` for their units)
//!
//! background = [0.1, 0.1, 0.1]  # a colour, a gradient, a map or a sun and sky
//!                                 # (`background_spec`)
//!
//! [render]                  # defaults that command-line flags override
//! width = 640
//! height = 640
//! spp = 1
//! max_depth = 2
//! patches_per_box = 1       # the GPU's boxes: one per run of this many patches (default:
//!                           # 1, or 4 where the scene does not fit the GPU's memory with 1)
//! hot_records = "packed"    # or "unpacked": 64 bytes a patch, read without decoding
//!                           # (default: unpacked for small point sets that fit so)
//! integrator = "whitted"    # or "path"
//! seed = 0                  # the path integrator's random sequence
//! ```
//!
//! Objects are described in `object_spec`, their transforms in `transform_spec` and their
//! materials in `material_spec`.

use std::path::{Path, PathBuf};

use serde::Deserialize;

pub use crate::background_spec::{BackgroundSpec, GradientSpec, MapSpec, SunSkySpec};
use crate::checks;
use crate::error::{InvalidValue, SceneError};
use crate::object_spec::{ObjectSpec, ShapeSpec};
use crate::points_scene::PointsScene;
use crate::render_settings::RenderSetting;
use crate::render_space::RenderSpace;
use crate::{Background, Camera, HotRecords, Integrator, Light, RenderSettings};

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    pub camera: Option<CameraSpec>,
    #[serde(default)]
    pub lights: Vec<LightSpec>,
    pub background: Option<BackgroundSpec>,
    #[serde(default)]
    pub objects: Vec<ObjectSpec>,
    #[serde(default)]
    pub render: RenderSpec,
    /// The file this was read from; relative paths inside resolve against its folder.
    #[serde(skip)]
    pub path: PathBuf,
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSpec {
    pub position: [f64; 3],
    pub look_at: [f64; 3],
    #[serde(default = "default_up")]
    pub up: [f32; 3],
    #[serde(default = "default_vfov_degrees")]
    pub vfov_degrees: f32,
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum LightSpec {
    Point {
        position: [f64; 3],
        #[serde(default = "white")]
        color: [f32; 3],
        #[serde(default = "unit_intensity")]
        intensity: f32,
    },
    Directional {
        direction: [f32; 3],
        #[serde(default = "white")]
        color: [f32; 3],
        #[serde(default = "unit_intensity")]
        intensity: f32,
    },
    Sphere {
        center: [f64; 3],
        radius: f64,
        #[serde(default = "white")]
        color: [f32; 3],
        #[serde(default = "unit_intensity")]
        intensity: f32,
    },
    Quad {
        corner: [f64; 3],
        edge_u: [f64; 3],
        edge_v: [f64; 3],
        #[serde(default = "white")]
        color: [f32; 3],
        #[serde(default = "unit_intensity")]
        intensity: f32,
    },
}

/// Render defaults; each is `None` when the file does not set it.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderSpec {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub spp: Option<u32>,
    pub max_depth: Option<u32>,
    pub patches_per_box: Option<u32>,
    pub hot_records: Option<HotRecords>,
    pub integrator: Option<Integrator>,
    pub seed: Option<u32>,
}

/// Where a TOML error is and what it is, without the source line that `toml` quotes: a file
/// named as a scene by mistake (a system file, say) must not have its contents printed.
fn parse_message(error: &toml::de::Error, text: &str) -> String {
    match error.span() {
        Some(span) => {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.rsplit('\n').next().map_or(0, |start| start.chars().count()) + 1;
            format!("line {line}, column {column}: {}", error.message())
        }
        None => error.message().to_string(),
    }
}

fn default_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}

fn default_vfov_degrees() -> f32 {
    45.0
}

fn white() -> [f32; 3] {
    [1.0; 3]
}

fn unit_intensity() -> f32 {
    1.0
}

/// Shown when a scene file gives no background.
pub const DEFAULT_BACKGROUND: Background =
    Background::Gradient { top: glam::Vec3::new(0.55, 0.7, 0.9), bottom: glam::Vec3::splat(0.95) };

impl SceneFile {
    pub fn read(path: &Path) -> Result<Self, SceneError> {
        pointray_io::ensure_readable_file(path).map_err(|error| SceneError::Read {
            path: path.to_path_buf(),
            source: match error {
                pointray_io::IoError::Os { source, .. } => source,
                pointray_io::IoError::Unusable { problem, .. } => std::io::Error::other(problem),
                other => std::io::Error::other(other.to_string()),
            },
        })?;
        let text = std::fs::read_to_string(path)
            .map_err(|source| SceneError::Read { path: path.to_path_buf(), source })?;
        Self::parse(&text, path)
    }

    /// Parses and checks `text`; `path` names it in errors and anchors relative paths.
    pub fn parse(text: &str, path: &Path) -> Result<Self, SceneError> {
        let mut file: Self = toml::from_str(text)
            .map_err(|e| SceneError::Parse { path: path.to_path_buf(), message: parse_message(&e, text) })?;
        file.path = path.to_path_buf();
        file.check().map_err(|invalid| invalid.in_file(path))?;
        Ok(file)
    }

    /// The default scene for a bare points file (or patch store), with the file's
    /// conventional up axis (`PointsScene::conventional`).
    pub fn for_points_file(points: &Path) -> Self {
        PointsScene::conventional(points).scene_file(points)
    }

    /// Gives every points object without its own `columns` these (the command line's
    /// `--columns`).
    pub fn with_columns(mut self, spec: Option<&pointray_io::formats::ColumnSpec>) -> Self {
        for object in &mut self.objects {
            if let ShapeSpec::Points { columns: columns @ None, .. } = &mut object.shape {
                *columns = spec.cloned();
            }
        }
        self
    }

    /// `RenderSettings::default()` with the `[render]` table on top.
    pub fn render_settings(&self) -> Result<RenderSettings, SceneError> {
        self.render.settings().map_err(|invalid| invalid.in_file(&self.path))
    }

    /// Every file loading this scene reads: the scene file itself, each object's points,
    /// store or mesh file, and the background's map. No output may be any of them.
    pub fn input_files(&self) -> Vec<PathBuf> {
        let objects = self.objects.iter().filter_map(|object| match &object.shape {
            ShapeSpec::Points { path, .. } | ShapeSpec::Mesh { path } => Some(self.resolve(path)),
            _ => None,
        });
        let map = match &self.background {
            Some(BackgroundSpec::Map(spec)) => Some(self.resolve(&spec.map)),
            _ => None,
        };
        std::iter::once(self.path.clone()).chain(objects).chain(map).collect()
    }

    /// A path from the file, relative to the file's folder unless absolute.
    pub fn resolve(&self, relative: &Path) -> PathBuf {
        self.path.parent().unwrap_or(Path::new("")).join(relative)
    }

    /// The background, with its map read if it has one.
    pub(crate) fn background(&self) -> Result<Background, SceneError> {
        let invalid = |e: InvalidValue| e.in_file(&self.path);
        match &self.background {
            Some(BackgroundSpec::Map(spec)) => {
                let image =
                    pointray_io::read_environment_image(&self.resolve(&spec.map)).map_err(|source| {
                        SceneError::Input { scene: self.path.clone(), key: "background.map".into(), source }
                    })?;
                spec.to_background(&image).map_err(invalid)
            }
            Some(BackgroundSpec::SunSky(spec)) => {
                Ok(Background::Map(std::sync::Arc::new(spec.to_sun_sky().map_err(invalid)?.map())))
            }
            _ => self.plain_background().map_err(invalid),
        }
    }

    /// The background without a map, checked; for a map, only its settings are checked.
    fn plain_background(&self) -> Result<Background, InvalidValue> {
        match &self.background {
            None => Ok(DEFAULT_BACKGROUND),
            Some(BackgroundSpec::Solid(c)) => Ok(Background::Solid(checks::color("background", *c)?)),
            Some(BackgroundSpec::Gradient(GradientSpec { top, bottom })) => Ok(Background::Gradient {
                top: checks::color("background.top", *top)?,
                bottom: checks::color("background.bottom", *bottom)?,
            }),
            Some(BackgroundSpec::Map(spec)) => spec.checked().map(|_| DEFAULT_BACKGROUND),
            Some(BackgroundSpec::SunSky(spec)) => spec.to_sun_sky().map(|_| DEFAULT_BACKGROUND),
        }
    }

    /// Every check that needs no file (as `read` makes them), again: for a scene changed since
    /// it was read, such as a camera placed from the command line.
    pub fn recheck(&self) -> Result<(), SceneError> {
        self.check().map_err(|invalid| invalid.in_file(&self.path))
    }

    /// Every check that needs no file, so that a typo fails before any slow loading.
    fn check(&self) -> Result<(), InvalidValue> {
        if let Some(camera) = &self.camera {
            camera.to_camera(&RenderSpace::FILE).map_err(|e| e.within("camera"))?;
        }
        for (i, light) in self.lights.iter().enumerate() {
            light.to_light(&RenderSpace::FILE).map_err(|e| e.within(&format!("lights[{i}]")))?;
        }
        self.plain_background()?;
        self.render.settings()?;
        for (i, object) in self.objects.iter().enumerate() {
            let key = format!("objects[{i}]");
            object.shape.check().map_err(|e| e.within(&key))?;
            object.transform.to_daffine().map_err(|e| e.within(&format!("{key}.transform")))?;
            object.material.to_material().map_err(|e| e.within(&format!("{key}.material")))?;
            object.material.checked_ramp().map_err(|e| e.within(&format!("{key}.material")))?;
        }
        Ok(())
    }
}

impl CameraSpec {
    /// A camera at `position` looking at `look_at`, Y up, with a vertical field of view of
    /// `vfov_degrees` or the default.
    pub fn looking(position: [f64; 3], look_at: [f64; 3], vfov_degrees: Option<f32>) -> Self {
        Self {
            position,
            look_at,
            up: default_up(),
            vfov_degrees: vfov_degrees.unwrap_or_else(default_vfov_degrees),
        }
    }

    /// The camera in the scene's render space (`RenderSpace`).
    pub(crate) fn to_camera(&self, space: &RenderSpace) -> Result<Camera, InvalidValue> {
        let position = space.point(checks::finite_dvec3("position", self.position)?);
        let look_at = space.point(checks::finite_dvec3("look_at", self.look_at)?);
        let up = checks::nonzero_vec3("up", self.up)?;
        let forward = look_at - position;
        if forward.length_squared() == 0.0 {
            return Err(InvalidValue::new("look_at", "must differ from the camera position"));
        }
        if forward.normalize().as_vec3().cross(up.normalize()).length() < 1e-4 {
            return Err(InvalidValue::new("up", "must not be parallel to the viewing direction"));
        }
        if !(self.vfov_degrees > 0.0 && self.vfov_degrees < 180.0) {
            return Err(InvalidValue::new(
                "vfov_degrees",
                format!("must be between 0 and 180, got {}", self.vfov_degrees),
            ));
        }
        Ok(Camera {
            position: checks::placeable("position", position)?,
            look_at: checks::placeable("look_at", look_at)?,
            up,
            vertical_fov_degrees: self.vfov_degrees,
        })
    }
}

impl LightSpec {
    /// The light in the scene's render space (`RenderSpace`).
    pub(crate) fn to_light(&self, space: &RenderSpace) -> Result<Light, InvalidValue> {
        Ok(match self {
            Self::Point { position, color, intensity } => Light::Point {
                position: checks::placeable(
                    "position",
                    space.point(checks::finite_dvec3("position", *position)?),
                )?,
                color: checks::color("color", *color)?,
                intensity: checks::non_negative("intensity", *intensity)?,
                space_scale: space.scale as f32,
            },
            Self::Directional { direction, color, intensity } => Light::Directional {
                direction: checks::nonzero_vec3("direction", *direction)?.normalize(),
                color: checks::color("color", *color)?,
                intensity: checks::non_negative("intensity", *intensity)?,
            },
            Self::Sphere { center, radius, color, intensity } => Light::Sphere {
                center: checks::placeable("center", space.point(checks::finite_dvec3("center", *center)?))?,
                radius: checks::positive("radius", (*radius / space.scale) as f32)?,
                color: checks::color("color", *color)?,
                intensity: checks::non_negative("intensity", *intensity)?,
            },
            Self::Quad { corner, edge_u, edge_v, color, intensity } => {
                let edge = |key: &str, value: &[f64; 3]| {
                    checks::finite_dvec3(key, *value).map(|v| (v / space.scale).as_vec3())
                };
                let (edge_u, edge_v) = (edge("edge_u", edge_u)?, edge("edge_v", edge_v)?);
                if edge_u.cross(edge_v).length() == 0.0 {
                    return Err(InvalidValue::new(
                        "edge_v",
                        "must not be parallel to edge_u (nor either zero)",
                    ));
                }
                Light::Quad {
                    corner: checks::placeable(
                        "corner",
                        space.point(checks::finite_dvec3("corner", *corner)?),
                    )?,
                    edge_u,
                    edge_v,
                    color: checks::color("color", *color)?,
                    intensity: checks::non_negative("intensity", *intensity)?,
                }
            }
        })
    }
}

impl RenderSpec {
    /// `RenderSettings::default()` with this file's values on top.
    pub(crate) fn settings(&self) -> Result<RenderSettings, InvalidValue> {
        let default = RenderSettings::default();
        let value = |setting: RenderSetting, given: Option<u32>, default: u32| {
            given.map_or(Ok(default), |value| {
                setting.check(value).map_err(|problem| InvalidValue::new(setting.file_key(), problem))
            })
        };
        Ok(RenderSettings {
            width: value(RenderSetting::Width, self.width, default.width)?,
            height: value(RenderSetting::Height, self.height, default.height)?,
            samples_per_pixel: value(RenderSetting::SamplesPerPixel, self.spp, default.samples_per_pixel)?,
            max_depth: value(RenderSetting::MaxDepth, self.max_depth, default.max_depth)?,
            patches_per_box: self
                .patches_per_box
                .map(|value| {
                    let setting = RenderSetting::PatchesPerBox;
                    setting.check(value).map_err(|problem| InvalidValue::new(setting.file_key(), problem))
                })
                .transpose()?,
            hot_records: self.hot_records,
            integrator: self.integrator.unwrap_or(default.integrator),
            seed: self.seed.unwrap_or(default.seed),
            ..default
        })
    }
}
