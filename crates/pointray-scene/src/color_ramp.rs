//! Colour from a value per point (scanner intensity, height): a ramp of evenly spaced colour
//! stops that turns each patch's value into the colour the renderers already read from its
//! cold record, so that both renderers show it with no shader of their own.

use glam::Vec3;
use pointray_kernels::PatchCold;

use crate::error::InvalidValue;

/// Viridis (matplotlib's default colour map) at nine evenly spaced stops, sRGB 8-bit:
/// even in lightness, so equal intensity steps look equal, and readable when printed grey.
const VIRIDIS_SRGB: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 45, 123],
    [59, 82, 139],
    [44, 114, 142],
    [33, 145, 140],
    [40, 174, 128],
    [94, 201, 98],
    [173, 220, 48],
    [253, 231, 37],
];

/// The ramps that can be named in a scene file.
pub const RAMP_NAMES: [&str; 2] = ["grey", "viridis"];

/// Maps a value to linear RGB: values in `[low, high]` spread over the stops, linearly
/// between neighbouring stops; outside it they take the end stops.
#[derive(Clone, Debug, PartialEq)]
pub struct ColorRamp {
    stops: Vec<Vec3>,
    low: f32,
    high: f32,
}

impl ColorRamp {
    /// A named ramp over values `[0, 1]`; `None` for a name not in `RAMP_NAMES`.
    pub fn named(name: &str) -> Option<Self> {
        let stops = match name {
            "grey" => vec![Vec3::ZERO, Vec3::ONE],
            "viridis" => VIRIDIS_SRGB.iter().map(|&rgb| srgb8_to_linear(rgb)).collect(),
            _ => return None,
        };
        Some(Self { stops, low: 0.0, high: 1.0 })
    }

    /// A ramp through `stops` (linear RGB, as `diffuse`), evenly spaced over `[0, 1]`.
    pub(crate) fn from_stops(stops: Vec<Vec3>) -> Result<Self, InvalidValue> {
        if stops.len() < 2 {
            return Err(InvalidValue::new(
                "ramp",
                format!("needs at least 2 colour stops, got {}", stops.len()),
            ));
        }
        Ok(Self { stops, low: 0.0, high: 1.0 })
    }

    /// Spreads the ramp over `[low, high]` instead of `[0, 1]`: scanners often use a
    /// small part of their intensity range.
    pub(crate) fn over(self, low: f32, high: f32) -> Result<Self, InvalidValue> {
        if !(low.is_finite() && high.is_finite() && low < high) {
            return Err(InvalidValue::new(
                "intensity_range",
                format!("must be [low, high] with low < high, both finite, got [{low}, {high}]"),
            ));
        }
        Ok(Self { low, high, ..self })
    }

    /// The colour for `value`.
    pub fn color_at(&self, value: f32) -> Vec3 {
        let t = ((value - self.low) / (self.high - self.low)).clamp(0.0, 1.0);
        let position = t * (self.stops.len() - 1) as f32;
        let below = (position.floor() as usize).min(self.stops.len() - 2);
        self.stops[below].lerp(self.stops[below + 1], position - below as f32)
    }

    /// Replaces each record's colour by the ramp's colour for its value (one per record).
    pub fn recolor(&self, cold: &mut [PatchCold], values: impl IntoIterator<Item = f32>) {
        for (record, value) in cold.iter_mut().zip(values) {
            let rgb = (self.color_at(value).clamp(Vec3::ZERO, Vec3::ONE) * 255.0).round();
            record.set_rgb8([rgb.x as u8, rgb.y as u8, rgb.z as u8]);
        }
    }
}

fn srgb8_to_linear(rgb: [u8; 3]) -> Vec3 {
    let decode = |c: u8| {
        let c = f32::from(c) / 255.0;
        if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
    };
    Vec3::new(decode(rgb[0]), decode(rgb[1]), decode(rgb[2]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grey_is_the_identity_on_each_channel() {
        let grey = ColorRamp::named("grey").unwrap();
        assert_eq!(grey.color_at(0.25), Vec3::splat(0.25));
        assert_eq!(grey.color_at(-1.0), Vec3::ZERO);
        assert_eq!(grey.color_at(2.0), Vec3::ONE);
    }

    #[test]
    fn stops_are_evenly_spaced_and_interpolated() {
        let ramp = ColorRamp::from_stops(vec![Vec3::X, Vec3::Y, Vec3::Z]).unwrap();
        assert_eq!(ramp.color_at(0.0), Vec3::X);
        assert_eq!(ramp.color_at(0.5), Vec3::Y);
        assert_eq!(ramp.color_at(1.0), Vec3::Z);
        assert_eq!(ramp.color_at(0.75), Vec3::new(0.0, 0.5, 0.5));
        assert!(ColorRamp::from_stops(vec![Vec3::X]).is_err());
    }

    #[test]
    fn a_range_stretches_the_ramp() {
        let ramp = ColorRamp::named("grey").unwrap().over(0.1, 0.3).unwrap();
        assert!((ramp.color_at(0.2) - Vec3::splat(0.5)).length() < 1e-6);
        assert!(ColorRamp::named("grey").unwrap().over(0.3, 0.3).is_err());
    }

    #[test]
    fn viridis_runs_from_dark_purple_to_yellow_in_linear_rgb() {
        let viridis = ColorRamp::named("viridis").unwrap();
        let (start, end) = (viridis.color_at(0.0), viridis.color_at(1.0));
        assert!(start.z > start.x && start.z > start.y, "starts blue-purple: {start}");
        assert!(end.x > 0.9 && end.y > 0.7 && end.z < 0.05, "ends yellow: {end}");
        assert!(ColorRamp::named("jet").is_none());
    }

    #[test]
    fn recolor_keeps_the_intensity() {
        let mut cold = [PatchCold::from_rgb8([1, 2, 3], 0.5)];
        ColorRamp::named("grey").unwrap().recolor(&mut cold, [0.5]);
        assert_eq!(cold[0], PatchCold::from_rgb8([128, 128, 128], 0.5));
    }
}
