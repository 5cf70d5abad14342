//! The coordinates pointray can trace in f32. Beyond these, squared distances underflow or
//! overflow: neighbour searches stall on tiny clouds, bounding-volume builders divide by
//! infinite areas, and a render never ends or draws garbage. Every route checks its geometry
//! against this range before any build and refuses what lies outside with a clear error.

use std::ops::RangeInclusive;

use pointray_io::TriangleMesh;
use pointray_kernels::Aabb;

/// The extents (bounding-box diagonals) a cloud may have, in its own units: `prep` works in
/// f32 on the recentred cloud.
pub const CLOUD_EXTENTS: RangeInclusive<f64> = 1e-9..=1e12;

/// The extents a scene's objects may span together, in file units: the loader places them in
/// f64 and scales the scene to a size near 1 (`pointray_scene::RenderSpace`), so only f32's
/// own range for the transforms bounds it.
pub const SCENE_EXTENTS: RangeInclusive<f64> = 1e-30..=1e30;

/// The largest magnitude of a local (recentred) coordinate: a cloud within `CLOUD_EXTENTS`
/// stays far below it, and products of two such numbers stay finite in f32.
pub const MAX_COORDINATE: f32 = 1e15;

/// Why `extent` cannot be traced, if it cannot; `what` names the thing measured and `range`
/// is what it may span.
pub fn extent_problem(what: &str, extent: f64, range: &RangeInclusive<f64>) -> Option<String> {
    let (min, max) = (*range.start(), *range.end());
    if !extent.is_finite() {
        return Some(format!("{what} has no finite extent"));
    }
    if extent < min {
        return Some(format!(
            "{what} spans only {extent:e} units, below the {min:e} that f32 maths can resolve: \
             scale the coordinates up"
        ));
    }
    if extent > max {
        return Some(format!(
            "{what} spans {extent:e} units, beyond the {max:e} that f32 maths can hold: \
             scale the coordinates down"
        ));
    }
    None
}

/// Whether every number of `value` is finite and within `MAX_COORDINATE`.
pub fn coordinates_in_range(values: &[f32]) -> bool {
    values.iter().all(|v| v.is_finite() && v.abs() <= MAX_COORDINATE)
}

/// A box whose corners are in range and ordered.
pub fn box_in_range(aabb: &Aabb) -> bool {
    coordinates_in_range(&aabb.min)
        && coordinates_in_range(&aabb.max)
        && (0..3).all(|axis| aabb.min[axis] <= aabb.max[axis])
}

/// The first vertex of `mesh` that is not finite or beyond `MAX_COORDINATE`.
pub fn first_vertex_out_of_range(mesh: &TriangleMesh) -> Option<usize> {
    mesh.positions.iter().position(|p| !coordinates_in_range(&p.to_array()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extents_outside_the_range_are_explained() {
        assert_eq!(extent_problem("the cloud", 0.2, &CLOUD_EXTENTS), None);
        assert!(
            extent_problem("the cloud", 3e-26, &CLOUD_EXTENTS).unwrap().contains("scale the coordinates up")
        );
        assert!(
            extent_problem("the cloud", 2e19, &CLOUD_EXTENTS).unwrap().contains("scale the coordinates down")
        );
        assert_eq!(extent_problem("the scene", 2e19, &SCENE_EXTENTS), None);
        assert!(extent_problem("the cloud", f64::NAN, &CLOUD_EXTENTS).is_some());
    }

    #[test]
    fn boxes_must_be_finite_ordered_and_in_range() {
        assert!(box_in_range(&Aabb::new([-1.0; 3].into(), [1.0; 3].into())));
        assert!(!box_in_range(&Aabb::new([f32::NAN; 3].into(), [1.0; 3].into())));
        assert!(!box_in_range(&Aabb::new([-1e38; 3].into(), [1e38; 3].into())));
        assert!(!box_in_range(&Aabb::new([1.0; 3].into(), [-1.0; 3].into())));
    }
}
