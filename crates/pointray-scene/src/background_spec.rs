//! The scene file's `background`: a colour, a gradient, an HDR map or a procedural sun and
//! sky.
//!
//! ```toml
//! background = [0.1, 0.1, 0.1]
//! background = { top = [0.5, 0.7, 1.0], bottom = [1.0, 1.0, 1.0] }
//! background = { map = "sky.exr", intensity = 1.0, rotation_degrees = 0.0 }
//! background = { sun_elevation_degrees = 35.0, sun_azimuth_degrees = 120.0 }
//! ```
//!
//! A map is equirectangular (`.exr` or `.hdr`, twice as wide as tall), with +y up and the
//! top row straight up, as Mitsuba 3 reads it; `rotation_degrees` turns it about +y. The sun
//! and sky also take `sun_radius_degrees` (2), `sun_intensity` (the sun's irradiance on a
//! surface facing it, 4) and `sky_intensity` (1).

use std::path::PathBuf;
use std::sync::Arc;

use pointray_kernels::EnvironmentMap;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer};

use crate::checks;
use crate::error::InvalidValue;
use crate::{Background, SunSky};

#[derive(Clone, Debug, PartialEq)]
pub enum BackgroundSpec {
    Solid([f32; 3]),
    Gradient(GradientSpec),
    Map(MapSpec),
    SunSky(SunSkySpec),
}

// Chosen by the value's shape rather than `untagged`, which would hide the table's own error
// (such as an unknown key) behind "did not match any variant".
impl<'de> Deserialize<'de> for BackgroundSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        match toml::Value::deserialize(deserializer)? {
            toml::Value::Table(table) if table.contains_key("map") => {
                MapSpec::deserialize(toml::Value::Table(table)).map(Self::Map)
            }
            toml::Value::Table(table)
                if table.keys().any(|k| k.starts_with("sun_") || k.starts_with("sky_")) =>
            {
                SunSkySpec::deserialize(toml::Value::Table(table)).map(Self::SunSky)
            }
            table @ toml::Value::Table(_) => GradientSpec::deserialize(table).map(Self::Gradient),
            other => <[f32; 3]>::deserialize(other).map(Self::Solid),
        }
        .map_err(|e| D::Error::custom(e.message()))
    }
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GradientSpec {
    pub top: [f32; 3],
    pub bottom: [f32; 3],
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MapSpec {
    /// Relative to the scene file's folder.
    pub map: PathBuf,
    #[serde(default = "one")]
    pub intensity: f32,
    #[serde(default)]
    pub rotation_degrees: f32,
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SunSkySpec {
    pub sun_elevation_degrees: f32,
    #[serde(default)]
    pub sun_azimuth_degrees: f32,
    #[serde(default = "default_sun_radius")]
    pub sun_radius_degrees: f32,
    #[serde(default = "default_sun_intensity")]
    pub sun_intensity: f32,
    #[serde(default = "one")]
    pub sky_intensity: f32,
}

fn one() -> f32 {
    1.0
}

fn default_sun_radius() -> f32 {
    2.0
}

fn default_sun_intensity() -> f32 {
    4.0
}

impl MapSpec {
    /// The map's scale and rotation (in turns), checked.
    pub(crate) fn checked(&self) -> Result<(f32, f32), InvalidValue> {
        let intensity = checks::non_negative("background.intensity", self.intensity)?;
        if !self.rotation_degrees.is_finite() {
            return Err(InvalidValue::new("background.rotation_degrees", "must be finite"));
        }
        Ok((intensity, self.rotation_degrees / 360.0))
    }

    /// The map from the image read from `map`, scaled and rotated.
    pub(crate) fn to_background(&self, image: &pointray_io::LinearImage) -> Result<Background, InvalidValue> {
        let (intensity, rotation) = self.checked()?;
        let radiance: Vec<_> = image.pixels.iter().map(|&t| t * intensity).collect();
        Ok(Background::Map(Arc::new(EnvironmentMap::new(image.width, image.height, &radiance, rotation))))
    }
}

impl SunSkySpec {
    pub(crate) fn to_sun_sky(&self) -> Result<SunSky, InvalidValue> {
        let within = |key: &str, value: f32, low: f32, high: f32| {
            if value.is_finite() && (low..=high).contains(&value) {
                Ok(value)
            } else {
                Err(InvalidValue::new(
                    format!("background.{key}"),
                    format!("must lie in [{low}, {high}], got {value}"),
                ))
            }
        };
        Ok(SunSky {
            sun_elevation_degrees: within("sun_elevation_degrees", self.sun_elevation_degrees, -90.0, 90.0)?,
            sun_azimuth_degrees: within("sun_azimuth_degrees", self.sun_azimuth_degrees, -360.0, 360.0)?,
            sun_radius_degrees: within("sun_radius_degrees", self.sun_radius_degrees, 0.25, 45.0)?,
            sun_intensity: checks::non_negative("background.sun_intensity", self.sun_intensity)?,
            sky_intensity: checks::non_negative("background.sky_intensity", self.sky_intensity)?,
        })
    }
}
