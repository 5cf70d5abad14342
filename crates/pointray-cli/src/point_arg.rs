//! Points given on the command line, `x,y,z`.

use glam::DVec3;

/// Parses `x,y,z`.
pub fn parse_point(text: &str) -> Result<DVec3, String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|part| part.trim().parse::<f64>().map_err(|e| format!("`{part}`: {e}")))
        .collect::<Result<_, _>>()?;
    match values[..] {
        [x, y, z] => Ok(DVec3::new(x, y, z)),
        _ => Err(format!("expected x,y,z, got `{text}`")),
    }
}

/// Parses `x,y,z` and refuses NaN and infinities.
pub fn parse_finite(text: &str) -> Result<DVec3, String> {
    let point = parse_point(text)?;
    if !point.is_finite() {
        return Err(format!("`{text}` is not a finite point"));
    }
    Ok(point)
}
