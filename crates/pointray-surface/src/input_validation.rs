//! The checks `prep` makes before it touches a point set, so that bad input gives a
//! clear error instead of NaN patches or a panic deep in a stage.

use glam::DVec3;
use rayon::prelude::*;

use pointray_io::MemoryBudget;
use pointray_patches::geometry_range::{CLOUD_EXTENTS, extent_problem};
use pointray_patches::{InvalidSetting, PrepSettings};

use crate::prep_error::PrepError;
use crate::prep_memory::{PREP_FIXED_BYTES, prep_bytes_per_point};

/// Points within this fraction of the cloud's extent of one line are judged collinear:
/// after recentring to f32 (24-bit mantissa) their offsets from the line are noise.
const COLLINEAR_TOLERANCE: f64 = 1e-6;

/// Every prep setting, whichever route it came by (flags, a scene file, code), checked by
/// `PrepSettings::check`.
pub fn validate_settings(settings: &PrepSettings) -> Result<(), PrepError> {
    settings
        .check()
        .map_err(|InvalidSetting { setting, problem }| PrepError::InvalidSetting { setting, problem })
}

/// Whether prepping `points` points with `params` (and attributes of `attribute_bytes` a
/// point) fits in `budget`, checked before any stage allocates.
pub fn validate_size(
    points: usize,
    settings: &PrepSettings,
    attribute_bytes: u64,
    budget: &MemoryBudget,
) -> Result<(), PrepError> {
    let bytes_each = prep_bytes_per_point(settings, attribute_bytes);
    let budget = MemoryBudget { bytes: budget.bytes.saturating_sub(PREP_FIXED_BYTES) };
    budget
        .check(points as u64, bytes_each, "points to prep")
        .map_err(|shortfall| PrepError::TooLarge { problem: shortfall.to_string() })
}

/// Refuses a NaN or infinite intensity, naming its point: prepped, it would reach the
/// store's cold records, and a store holding one is refused by every renderer that loads it.
pub fn validate_intensities(intensities: Option<&[f32]>) -> Result<(), PrepError> {
    let Some(values) = intensities else { return Ok(()) };
    match values.par_iter().position_first(|value| !value.is_finite()) {
        Some(index) => Err(PrepError::NonFiniteIntensity { index }),
        None => Ok(()),
    }
}

/// Checks, in order: finite coordinates, enough points, not all identical, not all on
/// one line.
pub fn validate_positions(positions: &[DVec3], k: usize) -> Result<(), PrepError> {
    validate_finite_count(positions, k)?;
    let count = positions.len();
    let line = LineThrough::points(positions);
    if line.extent == 0.0 {
        return Err(PrepError::AllPointsIdentical { count });
    }
    // Measured from one point, the extent is at least half the bounding box's diagonal.
    if let Some(problem) = extent_problem("the cloud", line.extent, &CLOUD_EXTENTS) {
        return Err(PrepError::ExtentOutOfRange { problem });
    }
    if line.holds_all(positions) {
        return Err(PrepError::AllPointsCollinear { count });
    }
    Ok(())
}

/// The checks a part of a cloud (a tile) can make for the whole of it, the cloud having
/// `points` points within the box `bounds`: finite coordinates and enough points, and not on
/// one line through opposite corners of the box, as every part of a collinear cloud is. A
/// part on another line (a pole, a wire) is no fault of the cloud.
pub fn validate_part(
    positions: &[DVec3],
    k: usize,
    (bounds, points): ((DVec3, DVec3), usize),
) -> Result<(), PrepError> {
    validate_finite_count(positions, k)?;
    let line = LineThrough::points(positions);
    let (min, max) = bounds;
    let diagonal = (max - min).length();
    let tolerance = COLLINEAR_TOLERANCE * diagonal;
    let on_diagonal = (0..4).any(|corner| {
        let flip = DVec3::new(f64::from(corner & 1), f64::from((corner >> 1) & 1), 0.0);
        let start = min + (max - min) * flip;
        let end = max - (max - min) * flip;
        line.distance_to(start) <= tolerance && line.distance_to(end) <= tolerance
    });
    if line.extent > 0.0 && on_diagonal && line.holds_all(positions) {
        return Err(PrepError::AllPointsCollinear { count: points });
    }
    Ok(())
}

/// The checks of the whole cloud's box (`min`, `max`) that a prep in parts makes first.
pub fn validate_bounds(min: DVec3, max: DVec3, points: usize) -> Result<(), PrepError> {
    let diagonal = (max - min).length();
    if diagonal == 0.0 {
        return Err(PrepError::AllPointsIdentical { count: points });
    }
    match extent_problem("the cloud", diagonal / 2.0, &CLOUD_EXTENTS) {
        Some(problem) => Err(PrepError::ExtentOutOfRange { problem }),
        None => Ok(()),
    }
}

fn validate_finite_count(positions: &[DVec3], k: usize) -> Result<(), PrepError> {
    if let Some(index) = positions.par_iter().position_first(|p| !p.is_finite()) {
        return Err(PrepError::NonFiniteCoordinate { index });
    }
    if positions.len() < k + 1 {
        return Err(PrepError::TooFewPoints { found: positions.len(), k });
    }
    Ok(())
}

/// The line from a set's first point to the point farthest from it.
struct LineThrough {
    anchor: DVec3,
    /// Unit length; zero when every point is the anchor.
    direction: DVec3,
    extent: f64,
}

impl LineThrough {
    fn points(positions: &[DVec3]) -> Self {
        let anchor = positions[0];
        let farthest = farthest_from(positions, anchor);
        let extent = (farthest - anchor).length();
        let direction = if extent > 0.0 { (farthest - anchor) / extent } else { DVec3::ZERO };
        Self { anchor, direction, extent }
    }

    fn distance_to(&self, point: DVec3) -> f64 {
        let offset = point - self.anchor;
        (offset - offset.dot(self.direction) * self.direction).length()
    }

    /// Whether every point lies within `COLLINEAR_TOLERANCE` of the extent of the line.
    fn holds_all(&self, positions: &[DVec3]) -> bool {
        let off_line = positions.par_iter().map(|&p| self.distance_to(p)).reduce(|| 0.0, f64::max);
        off_line <= COLLINEAR_TOLERANCE * self.extent
    }
}

fn farthest_from(positions: &[DVec3], anchor: DVec3) -> DVec3 {
    positions.par_iter().copied().reduce(
        || anchor,
        |a, b| if a.distance_squared(anchor) >= b.distance_squared(anchor) { a } else { b },
    )
}

#[cfg(test)]
mod tests {
    use pointray_patches::OutlierFilter;

    use super::*;

    fn grid(n: usize) -> Vec<DVec3> {
        (0..n * n).map(|i| DVec3::new((i % n) as f64, (i / n) as f64, 0.0)).collect()
    }

    #[test]
    fn accepts_a_plane_and_names_the_bad_point() {
        let mut points = grid(5);
        assert_eq!(validate_positions(&points, 9), Ok(()));
        points[7].y = f64::NAN;
        assert_eq!(validate_positions(&points, 9), Err(PrepError::NonFiniteCoordinate { index: 7 }));
        points[7].y = 0.0;
        points[3].z = f64::NEG_INFINITY;
        assert_eq!(validate_positions(&points, 9), Err(PrepError::NonFiniteCoordinate { index: 3 }));
    }

    #[test]
    fn refuses_degenerate_sets() {
        assert_eq!(validate_positions(&grid(3), 9), Err(PrepError::TooFewPoints { found: 9, k: 9 }));
        let same = vec![DVec3::new(1.0, 2.0, 3.0); 20];
        assert_eq!(validate_positions(&same, 9), Err(PrepError::AllPointsIdentical { count: 20 }));
        let line: Vec<DVec3> = (0..20).map(|i| DVec3::new(1.0, 2.0, 3.0) * i as f64).collect();
        assert_eq!(validate_positions(&line, 9), Err(PrepError::AllPointsCollinear { count: 20 }));
    }

    #[test]
    fn refuses_clouds_too_small_or_too_large_for_f32() {
        for scale in [1e-25, 1e-30, 1e15, 1e30] {
            let points: Vec<DVec3> = grid(5).into_iter().map(|p| p * scale).collect();
            let error = validate_positions(&points, 9).unwrap_err();
            assert!(matches!(error, PrepError::ExtentOutOfRange { .. }), "scale {scale}: {error}");
        }
        let millimetres: Vec<DVec3> = grid(5).into_iter().map(|p| p * 1e-3 + DVec3::splat(5e6)).collect();
        assert_eq!(validate_positions(&millimetres, 9), Ok(()));
    }

    #[test]
    fn refuses_bad_settings() {
        let few = PrepSettings { k: 2, ..PrepSettings::default() };
        assert!(matches!(validate_settings(&few), Err(PrepError::InvalidSetting { setting: "k", .. })));
        let many = PrepSettings { normal_k: 4_000_000_000, ..PrepSettings::default() };
        assert!(matches!(
            validate_settings(&many),
            Err(PrepError::InvalidSetting { setting: "normal_k", .. })
        ));
        let nan = PrepSettings { duplicate_tolerance: f32::NAN, ..PrepSettings::default() };
        assert!(matches!(validate_settings(&nan), Err(PrepError::InvalidSetting { .. })));
        assert_eq!(validate_settings(&PrepSettings::default()), Ok(()));
    }

    #[test]
    fn refuses_a_sensor_off_the_map_and_a_bad_outlier_filter() {
        let nan_sensor =
            PrepSettings { sensor: Some(DVec3::new(f64::NAN, 0.0, 0.0)), ..PrepSettings::default() };
        assert!(matches!(
            validate_settings(&nan_sensor),
            Err(PrepError::InvalidSetting { setting: "sensor", .. })
        ));
        for (neighbors, sigmas) in [(0, 1.0), (8, f32::NAN), (8, -1.0)] {
            let filter = PrepSettings {
                remove_outliers: Some(OutlierFilter { neighbors, sigmas }),
                ..PrepSettings::default()
            };
            assert!(validate_settings(&filter).is_err(), "K = {neighbors}, N = {sigmas}");
        }
        let fine = PrepSettings {
            remove_outliers: Some(OutlierFilter { neighbors: 8, sigmas: 2.0 }),
            sensor: Some(DVec3::ONE),
            ..PrepSettings::default()
        };
        assert_eq!(validate_settings(&fine), Ok(()));
    }

    #[test]
    fn refuses_a_cloud_too_large_for_memory_and_says_what_fits() {
        let budget = MemoryBudget { bytes: 1 << 30 };
        assert_eq!(validate_size(1_000_000, &PrepSettings::default(), 0, &budget), Ok(()));
        let error =
            validate_size(4_000_000_000, &PrepSettings::default(), 0, &budget).unwrap_err().to_string();
        assert!(error.contains("4000000000 points to prep") && error.contains("at most about"), "{error}");
    }
}
