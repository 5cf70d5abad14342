//! The dense check from the sensor. Each return is checked through the centre of the pixel it
//! falls in, on an angular grid around its sensor, and not along its own ray. A surface of
//! needles, one on each return, meets every return's own ray but leaves the pixels between
//! returns empty; from the sensor it renders as needles with gaps, and this check sees it.

use glam::{DVec3, Vec3};
use pointray_cpu::CpuRenderer;
use pointray_kernels::Ray;
use pointray_scene::PatchAcceptance;
use rayon::prelude::*;
use serde::Serialize;

/// The grid's pixel, degrees: a 1920-pixel-wide camera with a 107° field of view.
pub const PIXEL_DEGREES: f64 = 0.056;

/// A pixel agrees with its return when the depth there lies within the larger of these of the
/// return's range: the pixel centre is up to half a pixel from the return's own ray, which
/// on ground seen at a grazing angle moves the hit by metres at long range.
pub const ABSOLUTE_TOLERANCE: f64 = 0.25;
pub const RANGE_TOLERANCE: f64 = 0.05;

/// What the pixels of the returns saw.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct PixelConsistency {
    pub pixel_degrees: f64,
    pub absolute_tolerance: f64,
    pub range_tolerance: f64,
    /// Returns checked (those at their own sensor's position have no pixel).
    pub pixels: usize,
    pub consistent: usize,
    /// Surface well before the return.
    pub floaters: usize,
    /// Surface well beyond the return, or none.
    pub holes: usize,
    pub consistent_fraction: Option<f64>,
    pub floater_fraction: Option<f64>,
    pub hole_fraction: Option<f64>,
}

/// Where a pixel's depth lies against its return.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PixelOutcome {
    Consistent,
    Floater,
    Hole,
}

/// Checks the pixel of each `chosen` return of `local` (recentred positions), seen from
/// `sensor_of` (recentred too), against `renderer`'s patches.
pub fn sensor_pixel_consistency(
    renderer: &CpuRenderer,
    local: &[Vec3],
    sensor_of: impl Fn(usize) -> DVec3 + Sync,
    chosen: &[usize],
    acceptance: PatchAcceptance,
) -> PixelConsistency {
    let outcomes: Vec<PixelOutcome> = chosen
        .par_iter()
        .filter_map(|&i| {
            let sensor = sensor_of(i);
            let to_return = local[i].as_dvec3() - sensor;
            let range = to_return.length();
            let direction = pixel_centre(to_return)?;
            let ray = Ray::new(sensor.as_vec3(), direction.as_vec3());
            let depth = renderer.first_hit(&ray, 0.0, f32::INFINITY, acceptance).map(|hit| f64::from(hit.t));
            Some(classify(depth, range))
        })
        .collect();
    tally(&outcomes)
}

/// The direction through the centre of the grid pixel that `offset` (from the sensor) falls
/// in; `None` for a return at the sensor.
fn pixel_centre(offset: DVec3) -> Option<DVec3> {
    let horizontal = offset.x.hypot(offset.y);
    if offset.length() <= 0.0 || !offset.is_finite() {
        return None;
    }
    let pixel = PIXEL_DEGREES.to_radians();
    let centre = |angle: f64| ((angle / pixel).floor() + 0.5) * pixel;
    let (azimuth, elevation) = (centre(offset.y.atan2(offset.x)), centre(offset.z.atan2(horizontal)));
    Some(DVec3::new(azimuth.cos() * elevation.cos(), azimuth.sin() * elevation.cos(), elevation.sin()))
}

fn classify(depth: Option<f64>, range: f64) -> PixelOutcome {
    let tolerance = ABSOLUTE_TOLERANCE.max(RANGE_TOLERANCE * range);
    match depth {
        Some(depth) if (depth - range).abs() <= tolerance => PixelOutcome::Consistent,
        Some(depth) if depth < range => PixelOutcome::Floater,
        _ => PixelOutcome::Hole,
    }
}

fn tally(outcomes: &[PixelOutcome]) -> PixelConsistency {
    let count = |kind: PixelOutcome| outcomes.iter().filter(|&&o| o == kind).count();
    let pixels = outcomes.len();
    let fraction = |n: usize| (pixels > 0).then(|| n as f64 / pixels as f64);
    let (consistent, floaters, holes) =
        (count(PixelOutcome::Consistent), count(PixelOutcome::Floater), count(PixelOutcome::Hole));
    PixelConsistency {
        pixel_degrees: PIXEL_DEGREES,
        absolute_tolerance: ABSOLUTE_TOLERANCE,
        range_tolerance: RANGE_TOLERANCE,
        pixels,
        consistent,
        floaters,
        holes,
        consistent_fraction: fraction(consistent),
        floater_fraction: fraction(floaters),
        hole_fraction: fraction(holes),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixel_centre_lies_within_half_a_pixel_of_its_return() {
        let offset = DVec3::new(10.0, 3.0, -1.5);
        let centre = pixel_centre(offset).unwrap();
        let angle = centre.angle_between(offset).to_degrees();
        assert!(angle <= PIXEL_DEGREES * 0.71, "{angle}");
        assert!(pixel_centre(DVec3::ZERO).is_none());
    }

    #[test]
    fn depths_split_at_the_larger_tolerance() {
        assert_eq!(classify(Some(10.2), 10.0), PixelOutcome::Consistent);
        assert_eq!(classify(Some(9.4), 10.0), PixelOutcome::Floater);
        assert_eq!(classify(Some(104.0), 100.0), PixelOutcome::Consistent);
        assert_eq!(classify(Some(106.0), 100.0), PixelOutcome::Hole);
        assert_eq!(classify(None, 100.0), PixelOutcome::Hole);
    }
}
