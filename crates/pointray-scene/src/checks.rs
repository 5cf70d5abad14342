//! Range checks shared by the parts of the scene file.

use glam::{DVec3, Vec3};

use crate::error::InvalidValue;

pub(crate) fn finite_vec3(key: &str, value: [f32; 3]) -> Result<Vec3, InvalidValue> {
    let v = Vec3::from(value);
    if v.is_finite() { Ok(v) } else { Err(InvalidValue::new(key, format!("must be finite, got {value:?}"))) }
}

/// A position, kept in f64 so that geo-referenced coordinates keep their centimetres until
/// the scene is recentred.
pub(crate) fn finite_dvec3(key: &str, value: [f64; 3]) -> Result<DVec3, InvalidValue> {
    let v = DVec3::from(value);
    if v.is_finite() { Ok(v) } else { Err(InvalidValue::new(key, format!("must be finite, got {value:?}"))) }
}

/// A position in the render space, as f32: refused when it lies so far out (a camera 1e120
/// units away, say) that f32 cannot hold it.
pub(crate) fn placeable(key: &str, position: DVec3) -> Result<Vec3, InvalidValue> {
    let limit = f64::from(pointray_patches::geometry_range::MAX_COORDINATE);
    if position.abs().max_element() <= limit {
        Ok(position.as_vec3())
    } else {
        Err(InvalidValue::new(
            key,
            format!("lies {:e} scene sizes from the objects, beyond what f32 can place", position.length()),
        ))
    }
}

pub(crate) fn nonzero_vec3(key: &str, value: [f32; 3]) -> Result<Vec3, InvalidValue> {
    let v = finite_vec3(key, value)?;
    if v.length_squared() > 0.0 { Ok(v) } else { Err(InvalidValue::new(key, "must not be the zero vector")) }
}

/// Linear RGB; above 1 is allowed (bright lights), below 0 is not.
pub(crate) fn color(key: &str, value: [f32; 3]) -> Result<Vec3, InvalidValue> {
    let v = finite_vec3(key, value)?;
    if v.min_element() >= 0.0 {
        Ok(v)
    } else {
        Err(InvalidValue::new(key, format!("colour components must be >= 0, got {value:?}")))
    }
}

pub(crate) fn non_negative(key: &str, value: f32) -> Result<f32, InvalidValue> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(InvalidValue::new(key, format!("must be a finite number >= 0, got {value}")))
    }
}

pub(crate) fn positive(key: &str, value: f32) -> Result<f32, InvalidValue> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(InvalidValue::new(key, format!("must be a finite number > 0, got {value}")))
    }
}

pub(crate) fn in_unit_interval(key: &str, value: f32) -> Result<f32, InvalidValue> {
    if (0.0..=1.0).contains(&value) {
        Ok(value)
    } else {
        Err(InvalidValue::new(key, format!("must be in [0, 1], got {value}")))
    }
}

pub(crate) fn at_least(key: &str, value: u32, minimum: u32) -> Result<u32, InvalidValue> {
    if value >= minimum {
        Ok(value)
    } else {
        Err(InvalidValue::new(key, format!("must be at least {minimum}, got {value}")))
    }
}
