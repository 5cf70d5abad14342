//! The checks `prep` makes before it touches a point set, so that bad input gives a
//! clear error instead of NaN patches or a panic deep in a stage.

use glam::DVec3;
use rayon::prelude::*;

use crate::patch_set::PrepParams;
use crate::prep_error::PrepError;

/// Fewer neighbours than this cannot give a PCA normal or a plane fit.
const MIN_NEIGHBOURS: u32 = 3;

/// Points within this fraction of the cloud's extent of one line are judged collinear:
/// after recentring to f32 (24-bit mantissa) their offsets from the line are noise.
const COLLINEAR_TOLERANCE: f64 = 1e-6;

/// Beyond this, patches reach past twice their farthest neighbour: no longer local.
const MAX_DISK_SCALE: f32 = 2.0;

pub fn validate_params(params: &PrepParams) -> Result<(), PrepError> {
    let invalid = |problem: String| Err(PrepError::InvalidSettings { problem });
    if params.k < MIN_NEIGHBOURS || params.normal_k < MIN_NEIGHBOURS {
        return invalid(format!(
            "k = {} and normal_k = {} must both be at least {MIN_NEIGHBOURS}",
            params.k, params.normal_k
        ));
    }
    if !(params.duplicate_tolerance >= 0.0 && params.duplicate_tolerance.is_finite()) {
        return invalid(format!(
            "duplicate tolerance {} must be finite and >= 0",
            params.duplicate_tolerance
        ));
    }
    if !(params.disk_scale > 0.0 && params.disk_scale <= MAX_DISK_SCALE) {
        return invalid(format!("disk scale {} must be in (0, {MAX_DISK_SCALE}]", params.disk_scale));
    }
    Ok(())
}

/// Checks, in order: finite coordinates, enough points, not all identical, not all on
/// one line.
pub fn validate_positions(positions: &[DVec3], k: usize) -> Result<(), PrepError> {
    if let Some(index) = positions.par_iter().position_first(|p| !p.is_finite()) {
        return Err(PrepError::NonFiniteCoordinate { index });
    }
    if positions.len() < k + 1 {
        return Err(PrepError::TooFewPoints { found: positions.len(), k });
    }
    let count = positions.len();
    let anchor = positions[0];
    let farthest = farthest_from(positions, anchor);
    let extent = (farthest - anchor).length();
    if extent == 0.0 {
        return Err(PrepError::AllPointsIdentical { count });
    }
    let direction = (farthest - anchor) / extent;
    let off_line = positions
        .par_iter()
        .map(|p| {
            let offset = *p - anchor;
            (offset - offset.dot(direction) * direction).length()
        })
        .reduce(|| 0.0, f64::max);
    if off_line <= COLLINEAR_TOLERANCE * extent {
        return Err(PrepError::AllPointsCollinear { count });
    }
    Ok(())
}

fn farthest_from(positions: &[DVec3], anchor: DVec3) -> DVec3 {
    positions.par_iter().copied().reduce(
        || anchor,
        |a, b| if a.distance_squared(anchor) >= b.distance_squared(anchor) { a } else { b },
    )
}

#[cfg(test)]
mod tests {
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
    fn refuses_bad_settings() {
        let few = PrepParams { k: 2, ..PrepParams::default() };
        assert!(matches!(validate_params(&few), Err(PrepError::InvalidSettings { .. })));
        let nan = PrepParams { duplicate_tolerance: f32::NAN, ..PrepParams::default() };
        assert!(matches!(validate_params(&nan), Err(PrepError::InvalidSettings { .. })));
        assert_eq!(validate_params(&PrepParams::default()), Ok(()));
    }
}
