//! One `[[objects]]` entry of the scene file: a shape, with an optional name, transform and
//! material.
//!
//! ```toml
//! [[objects]]
//! type = "points"          # a points file (any format pointray-io reads) or a .patches store
//! path = "../data/points/bunny.ply"
//! columns = "x,y,z,intensity,ring"  # for text and raw .bin files: what each column holds
//! [objects.prep]           # optional: `pointray prep`'s settings, with its flags' names
//! k = 9
//! normal_k = 16
//! radius = "adaptive"      # support radius: "cell" (the default), "paper" or "adaptive"
//! remove_outliers = { neighbors = 8, sigmas = 2.0 }  # drop statistical outliers first
//!
//! [[objects]]
//! type = "mesh"            # PLY or OBJ
//! path = "bunny.obj"
//!
//! [[objects]]
//! type = "ground"          # a square in the plane y = height
//! auto = true              # at the other objects' lowest point, a few times their size
//! # height = 0.0           # or at a fixed height (then without `auto`)
//! # size = 10.0            # edge length; default: a few times the other objects' size
//!
//! [[objects]]
//! type = "sphere_points"   # points sampled on a sphere (no file needed)
//! center = [0.0, 1.0, 0.0]
//! radius = 1.0
//! count = 20000
//!
//! [[objects]]
//! type = "torus_points"    # points on a torus around the Y axis
//! major_radius = 1.0
//! minor_radius = 0.3
//! count = 20000
//! ```

use std::path::PathBuf;

use pointray_io::formats::ColumnSpec;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer};

use pointray_patches::PrepSettings;
use pointray_surface::PrepError;
use pointray_surface::input_validation::validate_settings;

use crate::checks;
use crate::error::InvalidValue;
use crate::material_spec::MaterialSpec;
use crate::transform_spec::TransformSpec;

#[derive(Clone, Debug, PartialEq)]
pub struct ObjectSpec {
    pub name: Option<String>,
    pub transform: TransformSpec,
    pub material: MaterialSpec,
    pub shape: ShapeSpec,
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeSpec {
    Points {
        path: PathBuf,
        /// Absent for a patch store, which is already prepped.
        prep: Option<PrepSettings>,
        #[serde(default, deserialize_with = "column_spec")]
        columns: Option<ColumnSpec>,
    },
    Mesh {
        path: PathBuf,
    },
    Ground {
        #[serde(default)]
        auto: bool,
        height: Option<f32>,
        size: Option<f32>,
    },
    SpherePoints {
        #[serde(default)]
        center: [f32; 3],
        radius: f32,
        count: u32,
    },
    TorusPoints {
        #[serde(default)]
        center: [f32; 3],
        major_radius: f32,
        minor_radius: f32,
        count: u32,
    },
}

impl ShapeSpec {
    /// The `type` string as written in the scene file.
    pub fn type_name(&self) -> &'static str {
        match self {
            Self::Points { .. } => "points",
            Self::Mesh { .. } => "mesh",
            Self::Ground { .. } => "ground",
            Self::SpherePoints { .. } => "sphere_points",
            Self::TorusPoints { .. } => "torus_points",
        }
    }

    /// A points object's prep settings, the defaults where the file gives none.
    pub fn prep_settings(&self) -> PrepSettings {
        match self {
            Self::Points { prep: Some(settings), .. } => *settings,
            _ => PrepSettings::default(),
        }
    }

    /// Range checks that need no file.
    pub(crate) fn check(&self) -> Result<(), InvalidValue> {
        match self {
            Self::Points { path, .. } => {
                if path.as_os_str().is_empty() {
                    return Err(InvalidValue::new("path", "must not be empty"));
                }
                validate_settings(&self.prep_settings()).map_err(|error| match error {
                    PrepError::InvalidSetting { setting, problem } => {
                        InvalidValue::new(format!("prep.{setting}"), problem)
                    }
                    other => InvalidValue::new("prep", other.to_string()),
                })?;
            }
            Self::Mesh { path } if path.as_os_str().is_empty() => {
                return Err(InvalidValue::new("path", "must not be empty"));
            }
            Self::Mesh { .. } => {}
            Self::Ground { auto, height, size } => {
                if *auto && height.is_some() {
                    return Err(InvalidValue::new(
                        "height",
                        "give either `auto = true` or a height, not both",
                    ));
                }
                height.map(|h| checks::finite_vec3("height", [h; 3])).transpose()?;
                size.map(|s| checks::positive("size", s)).transpose()?;
            }
            Self::SpherePoints { center, radius, count } => {
                checks::finite_vec3("center", *center)?;
                checks::positive("radius", *radius)?;
                checks::at_least("count", *count, MIN_PROCEDURAL_POINTS)?;
            }
            Self::TorusPoints { center, major_radius, minor_radius, count } => {
                checks::finite_vec3("center", *center)?;
                checks::positive("major_radius", *major_radius)?;
                checks::positive("minor_radius", *minor_radius)?;
                // A tube wider than its ring intersects itself: no longer a manifold surface.
                if minor_radius >= major_radius {
                    return Err(InvalidValue::new("minor_radius", "must be smaller than major_radius"));
                }
                checks::at_least("count", *count, MIN_PROCEDURAL_POINTS)?;
            }
        }
        Ok(())
    }
}

/// Enough points for prep's neighbourhoods with any sensible `k`.
const MIN_PROCEDURAL_POINTS: u32 = 64;

/// The keys every object may have, whatever its type.
const COMMON_KEYS: [&str; 3] = ["name", "transform", "material"];

// Hand-written because serde's `flatten` cannot be combined with `deny_unknown_fields`: the
// common keys are taken out first, and the rest must match exactly one shape.
impl<'de> Deserialize<'de> for ObjectSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let mut table = toml::Table::deserialize(deserializer)?;
        let [name, transform, material] = COMMON_KEYS.map(|key| table.remove(key));
        Ok(Self {
            name: name.map(|v| v.try_into().map_err(|e| field_error::<D>("name", e))).transpose()?,
            transform: transform
                .map(|v| v.try_into().map_err(|e| field_error::<D>("transform", e)))
                .transpose()?
                .unwrap_or_default(),
            material: material
                .map(|v| v.try_into().map_err(|e| field_error::<D>("material", e)))
                .transpose()?
                .unwrap_or_default(),
            shape: ShapeSpec::deserialize(toml::Value::Table(table)).map_err(D::Error::custom)?,
        })
    }
}

/// `columns = "x,y,z,intensity,ring"`, parsed with the file so that a bad name fails early.
fn column_spec<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Option<ColumnSpec>, D::Error> {
    let text = String::deserialize(deserializer)?;
    ColumnSpec::parse(&text).map(Some).map_err(D::Error::custom)
}

fn field_error<'de, D: Deserializer<'de>>(key: &str, error: toml::de::Error) -> D::Error {
    D::Error::custom(format!("{key}: {}", error.message()))
}
