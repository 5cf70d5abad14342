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
//! use_point_colors = false
//! ```

use serde::Deserialize;

use crate::Material;
use crate::checks;
use crate::error::InvalidValue;

#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    pub ambient: Option<f32>,
    pub diffuse: Option<[f32; 3]>,
    pub specular: Option<f32>,
    pub shininess: Option<f32>,
    pub reflectivity: Option<f32>,
    pub use_point_colors: Option<bool>,
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
            use_point_colors: self.use_point_colors.unwrap_or(default.use_point_colors),
        })
    }
}
