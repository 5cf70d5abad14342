//! An object's placement in the scene file: scale, then rotate, then translate.
//!
//! ```toml
//! [objects.transform]
//! translate = [0.0, 0.1, 0.0]
//! rotate = [-90.0, 0.0, 0.0]                   # Euler degrees about X, then Y, then Z
//! # rotate = { axis = [0, 1, 0], degrees = 30 } # or an axis and an angle
//! scale = 2.0                                  # or per axis: [1.0, 2.0, 1.0]
//! ```

use glam::{DAffine3, DVec3, Quat, Vec3};
use serde::de::Error as _;
use serde::{Deserialize, Deserializer};

use crate::checks;
use crate::error::InvalidValue;

#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformSpec {
    pub translate: Option<[f64; 3]>,
    pub rotate: Option<RotationSpec>,
    pub scale: Option<ScaleSpec>,
}

/// An array of Euler angles in degrees `[x, y, z]`, or a table `{ axis = [x, y, z], degrees = a }`.
#[derive(Clone, Debug, PartialEq)]
pub enum RotationSpec {
    /// Degrees about the X axis, then the Y axis, then the Z axis (fixed axes).
    EulerDegrees([f32; 3]),
    AxisAngle(AxisAngle),
}

// Chosen by the value's shape rather than `untagged`, which would hide the table's own
// error (such as an unknown key) behind "did not match any variant".
impl<'de> Deserialize<'de> for RotationSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        match toml::Value::deserialize(deserializer)? {
            table @ toml::Value::Table(_) => AxisAngle::deserialize(table).map(Self::AxisAngle),
            other => <[f32; 3]>::deserialize(other).map(Self::EulerDegrees),
        }
        .map_err(|e| D::Error::custom(e.message()))
    }
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisAngle {
    pub axis: [f32; 3],
    pub degrees: f32,
}

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(untagged, expecting = "a number (uniform scale) or an array [x, y, z]")]
pub enum ScaleSpec {
    Uniform(f32),
    PerAxis([f32; 3]),
}

impl TransformSpec {
    /// Object to world: `translate * rotate * scale`, in f64 so that a geo-referenced
    /// translation keeps its precision until the scene is recentred.
    pub(crate) fn to_daffine(&self) -> Result<DAffine3, InvalidValue> {
        let translation = match self.translate {
            Some(t) => checks::finite_dvec3("translate", t)?,
            None => DVec3::ZERO,
        };
        let rotation = match &self.rotate {
            Some(rotation) => rotation.to_quat()?,
            None => Quat::IDENTITY,
        };
        let scale = match &self.scale {
            Some(scale) => scale.to_vec3()?,
            None => Vec3::ONE,
        };
        Ok(DAffine3::from_scale_rotation_translation(scale.as_dvec3(), rotation.as_dquat(), translation))
    }
}

impl RotationSpec {
    fn to_quat(&self) -> Result<Quat, InvalidValue> {
        match self {
            Self::EulerDegrees(degrees) => {
                let [x, y, z] = checks::finite_vec3("rotate", *degrees)?.to_array().map(f32::to_radians);
                Ok(Quat::from_rotation_z(z) * Quat::from_rotation_y(y) * Quat::from_rotation_x(x))
            }
            Self::AxisAngle(AxisAngle { axis, degrees }) => {
                let axis = checks::nonzero_vec3("rotate.axis", *axis)?.normalize();
                if !degrees.is_finite() {
                    return Err(InvalidValue::new(
                        "rotate.degrees",
                        format!("must be finite, got {degrees}"),
                    ));
                }
                Ok(Quat::from_axis_angle(axis, degrees.to_radians()))
            }
        }
    }
}

impl ScaleSpec {
    fn to_vec3(&self) -> Result<Vec3, InvalidValue> {
        let scale = match self {
            Self::Uniform(s) => Vec3::splat(*s),
            Self::PerAxis(s) => Vec3::from(*s),
        };
        // A zero factor flattens the object and makes the transform singular; the renderers
        // invert it to bring rays into object space.
        if scale.is_finite() && scale.abs().min_element() > 0.0 {
            Ok(scale)
        } else {
            Err(InvalidValue::new("scale", format!("every factor must be finite and non-zero, got {scale}")))
        }
    }
}
