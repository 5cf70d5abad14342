//! The cameras a fidelity run asks for, before they are placed (`view_placement.rs`).

use std::str::FromStr;

use glam::Vec3;

use crate::FidelityError;
use crate::view_directions::MINIMUM_VIEWS;

/// Sensor views split the horizon into this many yaws at most and at least: fewer than 3
/// would need lenses of 180° or more, more than 12 make images many times taller than wide.
pub const SENSOR_YAWS: std::ops::RangeInclusive<u32> = 3..=12;
/// Four yaws of 90° each: the horizon in four square-pixelled quarter views.
pub const DEFAULT_SENSOR_YAWS: u32 = 4;
/// High enough over a street to see it as a map, low enough for the kerbs to show.
pub const DEFAULT_ABOVE_HEIGHT: f32 = 20.0;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ViewSpec {
    /// `count` cameras framing the whole mesh from directions spread around it
    /// (`view_directions`).
    Around { count: usize },
    /// One camera framing the whole mesh from `direction` (from its centre toward the camera).
    Direction(Vec3),
    /// A camera at `from` looking at `at`.
    Explicit { from: Vec3, at: Vec3 },
    /// `yaws` cameras at the sensor splitting the horizon, each as tall as the elevations
    /// the sensor's returns span.
    Sensor { yaws: u32 },
    /// One camera `height` above the points' centre (along the up axis), looking straight down.
    Above { height: f32 },
}

impl ViewSpec {
    /// Checks the numbers a spec carries; the placement checks what depends on the scene.
    pub fn validate(&self) -> Result<(), FidelityError> {
        let invalid = |reason: String| Err(FidelityError::InvalidView { view: self.to_string(), reason });
        match *self {
            ViewSpec::Around { count } if count < MINIMUM_VIEWS => {
                Err(FidelityError::TooFewViews { requested: count, minimum: MINIMUM_VIEWS })
            }
            ViewSpec::Direction(direction) if !direction.is_finite() || direction.length() == 0.0 => {
                invalid("the direction must be finite and non-zero".into())
            }
            ViewSpec::Explicit { from, at } if !from.is_finite() || !at.is_finite() => {
                invalid("the camera position and target must be finite".into())
            }
            ViewSpec::Explicit { from, at } if from == at => {
                invalid("the camera stands on its target, so it looks nowhere".into())
            }
            ViewSpec::Sensor { yaws } if !SENSOR_YAWS.contains(&yaws) => invalid(format!(
                "the horizon splits into {} to {} yaws",
                SENSOR_YAWS.start(),
                SENSOR_YAWS.end()
            )),
            ViewSpec::Above { height } if !(height.is_finite() && height > 0.0) => {
                invalid("the height must be a positive number".into())
            }
            _ => Ok(()),
        }
    }
}

/// `N` (N cameras around the mesh), `sensor`, `sensor:YAWS`, `above` or `above:HEIGHT`.
impl FromStr for ViewSpec {
    type Err = FidelityError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let text = text.trim();
        let (name, argument) = match text.split_once(':') {
            Some((name, argument)) => (name, Some(argument.trim())),
            None => (text, None),
        };
        let unknown = || FidelityError::UnknownView { text: text.to_owned() };
        let spec = match (name, argument) {
            ("sensor", None) => ViewSpec::Sensor { yaws: DEFAULT_SENSOR_YAWS },
            ("sensor", Some(yaws)) => ViewSpec::Sensor { yaws: yaws.parse().map_err(|_| unknown())? },
            ("above", None) => ViewSpec::Above { height: DEFAULT_ABOVE_HEIGHT },
            ("above", Some(height)) => ViewSpec::Above { height: height.parse().map_err(|_| unknown())? },
            (count, None) => ViewSpec::Around { count: count.parse().map_err(|_| unknown())? },
            _ => return Err(unknown()),
        };
        spec.validate()?;
        Ok(spec)
    }
}

impl std::fmt::Display for ViewSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ViewSpec::Around { count } => write!(f, "{count} around"),
            ViewSpec::Direction(d) => write!(f, "({:+.2}, {:+.2}, {:+.2})", d.x, d.y, d.z),
            ViewSpec::Explicit { from, at } => write!(f, "from {} at {}", point(*from), point(*at)),
            ViewSpec::Sensor { yaws } => write!(f, "sensor:{yaws}"),
            ViewSpec::Above { height } => write!(f, "above:{height}"),
        }
    }
}

fn point(p: Vec3) -> String {
    format!("({}, {}, {})", p.x, p.y, p.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_counts_and_arguments_parse() {
        assert_eq!("8".parse::<ViewSpec>().unwrap(), ViewSpec::Around { count: 8 });
        assert_eq!("sensor".parse::<ViewSpec>().unwrap(), ViewSpec::Sensor { yaws: 4 });
        assert_eq!(" sensor:6 ".parse::<ViewSpec>().unwrap(), ViewSpec::Sensor { yaws: 6 });
        assert_eq!("above".parse::<ViewSpec>().unwrap(), ViewSpec::Above { height: 20.0 });
        assert_eq!("above:35.5".parse::<ViewSpec>().unwrap(), ViewSpec::Above { height: 35.5 });
    }

    #[test]
    fn bad_views_name_the_problem() {
        let message = |text: &str| text.parse::<ViewSpec>().unwrap_err().to_string();
        assert!(message("below").contains("`below`"), "{}", message("below"));
        assert!(message("sensor:x").contains("`sensor:x`"));
        assert!(message("sensor:2").contains("3 to 12 yaws"), "{}", message("sensor:2"));
        assert!(message("above:-5").contains("positive"));
        assert!(message("above:nan").contains("positive"));
        assert!(message("above:inf").contains("positive"));
        assert!(message("3").contains("at least 6"), "{}", message("3"));
        assert!(message("8:2").contains("`8:2`"));
    }

    #[test]
    fn explicit_views_need_distinct_finite_points() {
        let same = ViewSpec::Explicit { from: Vec3::ONE, at: Vec3::ONE };
        assert!(same.validate().unwrap_err().to_string().contains("stands on its target"));
        let nan = ViewSpec::Explicit { from: Vec3::NAN, at: Vec3::ONE };
        assert!(nan.validate().unwrap_err().to_string().contains("finite"));
        assert!(ViewSpec::Explicit { from: Vec3::ZERO, at: Vec3::X }.validate().is_ok());
    }
}
