//! An object's material in the scene file; every key is optional and defaults to
//! `Material::default()`.
//!
//! ```toml
//! [objects.material]
//! ambient = 0.1
//! diffuse = [0.8, 0.7, 0.6]   # linear RGB
//! specular = 0.3
//! shininess = 32.0
//! reflectivity = 0.5          # 0 = none, 1 = a mirror
//! color_source = "fixed"      # "fixed" (diffuse), "points" (the file's RGB), "intensity",
//!                             # "height" or "classification" (the ASPRS palette)
//! ramp = "viridis"            # for "intensity" and "height": "grey", "viridis", or evenly
//!                             # spaced linear RGB stops, e.g. [[0, 0, 0.2], [1, 1, 0.8]]
//! intensity_range = [0.0, 1.0] # for "intensity": the intensities the ramp spans
//! bsdf = "plastic"            # the path integrator's: "phong" (the default, below),
//!                             # "diffuse", "conductor", "plastic" or "dielectric" (glass),
//!                             # each coloured by the base colour above
//! roughness = 0.1             # GGX alpha, 0 to 1 (0 makes glass smooth)
//! ior = 1.5                   # glass's and a plastic coating's index of refraction
//! emission = [0.0, 0.0, 0.0]  # radiance the surface emits (path integrator)
//! ```
//!
//! Under the path integrator a material without `bsdf` (every scene written for the Whitted
//! integrator) is Lambertian of its base colour, and with `reflectivity > 0` a glossy
//! plastic of that colour (GGX alpha `PHONG_REFLECTION_ROUGHNESS`, ior 1.5).
//!
//! `use_point_colors = true` (older scenes) means `color_source = "points"`, and `false`
//! means `"fixed"`; a material gives one key or the other, not both.

use serde::Deserialize;

use crate::Material;
use crate::checks;
use crate::color_ramp::{ColorRamp, RAMP_NAMES};
use crate::error::InvalidValue;
use crate::material::SurfaceKind;

/// Where a point set's diffuse colour comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ColorSource {
    /// The material's `diffuse`.
    #[default]
    Fixed,
    /// The points file's own colours.
    Points,
    /// The points' intensities through the `ramp`.
    Intensity,
    /// The points' height (world Y) through the `ramp`, from the object's lowest point to
    /// its highest.
    Height,
    /// The points' LAS classification, in the ASPRS palette.
    Classification,
    /// The points' own colours where they have them, else their intensities through the
    /// `ramp` (grey by default), else the material's `diffuse`: what a bare points file shows.
    Auto,
}

impl std::str::FromStr for ColorSource {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Self::deserialize(serde::de::value::StrDeserializer::<serde::de::value::Error>::new(text))
            .map_err(|_| format!("unknown colour source `{text}`; the sources are {COLOR_SOURCE_NAMES:?}"))
    }
}

const COLOR_SOURCE_NAMES: [&str; 6] = ["auto", "points", "intensity", "height", "classification", "fixed"];

/// A named ramp or a list of colour stops.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum RampSpec {
    Named(String),
    Stops(Vec<[f32; 3]>),
}

/// Without a `ramp`, intensities are shown in grey (no colour that the scan does not have)
/// and heights in viridis (even steps of height look even).
const DEFAULT_INTENSITY_RAMP: &str = "grey";
const DEFAULT_HEIGHT_RAMP: &str = "viridis";

#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    pub ambient: Option<f32>,
    pub diffuse: Option<[f32; 3]>,
    pub specular: Option<f32>,
    pub shininess: Option<f32>,
    pub reflectivity: Option<f32>,
    pub use_point_colors: Option<bool>,
    pub color_source: Option<ColorSource>,
    pub ramp: Option<RampSpec>,
    pub intensity_range: Option<[f32; 2]>,
    pub bsdf: Option<SurfaceKind>,
    pub roughness: Option<f32>,
    pub ior: Option<f32>,
    pub emission: Option<[f32; 3]>,
}

impl MaterialSpec {
    pub(crate) fn to_material(&self) -> Result<Material, InvalidValue> {
        let default = Material::default();
        Ok(Material {
            ambient: checks::non_negative("ambient", self.ambient.unwrap_or(default.ambient))?,
            diffuse: match self.diffuse {
                Some(diffuse) => checks::color("diffuse", diffuse)?,
                None => default.diffuse,
            },
            specular: checks::non_negative("specular", self.specular.unwrap_or(default.specular))?,
            shininess: checks::non_negative("shininess", self.shininess.unwrap_or(default.shininess))?,
            reflectivity: checks::in_unit_interval(
                "reflectivity",
                self.reflectivity.unwrap_or(default.reflectivity),
            )?,
            use_point_colors: self.color_source()? != ColorSource::Fixed,
            surface: self.bsdf.unwrap_or(default.surface),
            roughness: checks::in_unit_interval("roughness", self.roughness.unwrap_or(default.roughness))?,
            ior: checks::positive("ior", self.ior.unwrap_or(default.ior))?,
            emission: match self.emission {
                Some(emission) => checks::color("emission", emission)?,
                None => default.emission,
            },
        })
    }

    /// `color_source`, or what the older `use_point_colors` says.
    pub(crate) fn color_source(&self) -> Result<ColorSource, InvalidValue> {
        match (self.color_source, self.use_point_colors) {
            (Some(_), Some(_)) => Err(InvalidValue::new(
                "use_point_colors",
                "give either `color_source` or the older `use_point_colors`, not both",
            )),
            (Some(source), None) => Ok(source),
            (None, Some(true)) => Ok(ColorSource::Points),
            (None, Some(false) | None) => Ok(ColorSource::Fixed),
        }
    }

    /// Checks the ramp as loading will use it: under `"auto"`, as for intensities.
    pub(crate) fn checked_ramp(&self) -> Result<(), InvalidValue> {
        let source = match self.color_source()? {
            ColorSource::Auto => ColorSource::Intensity,
            source => source,
        };
        self.ramp(source).map(drop)
    }

    /// The ramp that colours the points by a value under `source` (the `color_source`, or what
    /// `"auto"` resolved to); `None` unless that is `"intensity"` or `"height"`. `ramp` is
    /// refused with any other source but `"auto"`, and `intensity_range` with any but
    /// `"intensity"` and `"auto"`.
    pub(crate) fn ramp(&self, source: ColorSource) -> Result<Option<ColorRamp>, InvalidValue> {
        let auto = self.color_source()? == ColorSource::Auto;
        if source != ColorSource::Intensity && !auto && self.intensity_range.is_some() {
            return Err(InvalidValue::new(
                "intensity_range",
                "applies only with `color_source = \"intensity\"`",
            ));
        }
        let default = match source {
            ColorSource::Intensity => DEFAULT_INTENSITY_RAMP,
            ColorSource::Height => DEFAULT_HEIGHT_RAMP,
            _ if self.ramp.is_some() && !auto => {
                return Err(InvalidValue::new(
                    "ramp",
                    "applies only with `color_source = \"intensity\"` or `\"height\"`",
                ));
            }
            _ => return Ok(None),
        };
        let ramp = match &self.ramp {
            None => ColorRamp::named(default).unwrap_or_else(|| unreachable!("a built-in ramp")),
            Some(RampSpec::Named(name)) => ColorRamp::named(name).ok_or_else(|| {
                InvalidValue::new(
                    "ramp",
                    format!("unknown ramp `{name}`; the named ramps are {RAMP_NAMES:?}"),
                )
            })?,
            Some(RampSpec::Stops(stops)) => {
                let colors =
                    stops.iter().map(|&stop| checks::color("ramp", stop)).collect::<Result<_, _>>()?;
                ColorRamp::from_stops(colors)?
            }
        };
        match self.intensity_range {
            Some([low, high]) => Ok(Some(ramp.over(low, high)?)),
            None => Ok(Some(ramp)),
        }
    }
}
