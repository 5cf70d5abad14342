//! The render space: scenes are loaded in f64, then recentred on their objects and scaled to a
//! size near 1 before anything goes to f32.
//! - Geo-referenced scenes sit 10^5 to 10^7 units from the origin, where an f32 keeps only
//!   decimetres to metres: rays, hits and BVH boxes there come out scattered or missing.
//! - The renderers' tolerances are in ray units (a quadratic is solved as linear when its far
//!   root lies beyond 10^6); a scene 10^10 across breaks them.
//!
//! In the render space the renderers see the same numbers as for the scene at the origin at
//! its usual size. The scale is a power of two, so scaling loses no bit.

use glam::{Affine3A, DAffine3, DVec3, Vec3};
use pointray_io::TriangleMesh;

use crate::Geometry;

/// A box in f64 file coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WorldBounds {
    pub min: DVec3,
    pub max: DVec3,
}

impl WorldBounds {
    pub fn union(self, other: Self) -> Self {
        Self { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    pub fn diagonal(&self) -> f64 {
        (self.max - self.min).length()
    }

    fn center(&self) -> DVec3 {
        (self.min + self.max) * 0.5
    }
}

/// The bounds of `geometry` placed by `local_to_world`, from the corners of its local box.
pub(crate) fn placed_bounds(geometry: &Geometry, local_to_world: &DAffine3) -> Option<WorldBounds> {
    let local = geometry.sample_bounds(|p| p)?;
    let (min, max) = (Vec3::from(local.min).as_dvec3(), Vec3::from(local.max).as_dvec3());
    let corner = |i: usize| {
        let pick = |axis: usize| if i & (1 << axis) == 0 { min[axis] } else { max[axis] };
        local_to_world.transform_point3(DVec3::new(pick(0), pick(1), pick(2)))
    };
    (0..8).map(|i| WorldBounds { min: corner(i), max: corner(i) }).reduce(WorldBounds::union)
}

/// Objects farther from the file's origin than this many times their own size are recentred:
/// nearer, f32 keeps their positions to a millionth of their size or better.
const RECENTRE_BEYOND_SIZES: f64 = 16.0;

/// Scenes whose size lies between these (in file units) keep their scale.
const USUAL_SIZES: std::ops::RangeInclusive<f64> = 1e-3..=1e4;

/// The render space in file coordinates: `file = origin + scale * render`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSpace {
    pub origin: DVec3,
    pub scale: f64,
}

impl RenderSpace {
    pub const FILE: Self = Self { origin: DVec3::ZERO, scale: 1.0 };

    /// The space for objects within `bounds` (file coordinates): recentred on them when they
    /// lie far from the file's origin for their size, and scaled by a power of two near their
    /// size when that is unusually small or large; else the file's own space, so that a scene
    /// of usual size near the origin renders exactly as written.
    pub(crate) fn around(bounds: Option<WorldBounds>) -> Self {
        let Some(bounds) = bounds else { return Self::FILE };
        let size = bounds.diagonal();
        let far = bounds.center().length() > RECENTRE_BEYOND_SIZES * size;
        let unusual = size > 0.0 && !USUAL_SIZES.contains(&size);
        Self {
            origin: if far { bounds.center() } else { DVec3::ZERO },
            scale: if unusual { 2f64.powi(size.log2().round() as i32) } else { 1.0 },
        }
    }

    /// A file position in the render space.
    pub fn point(&self, file: DVec3) -> DVec3 {
        (file - self.origin) / self.scale
    }

    /// A render-space position in the file's coordinates (after the objects' transforms).
    pub fn point_to_file(&self, render: DVec3) -> DVec3 {
        self.origin + render * self.scale
    }

    /// `local_to_file` seen from the render space, in f32.
    pub(crate) fn transform(&self, local_to_file: &DAffine3) -> Affine3A {
        let to_render =
            DAffine3::from_scale(DVec3::splat(1.0 / self.scale)) * DAffine3::from_translation(-self.origin);
        let placed = to_render * *local_to_file;
        Affine3A::from_mat3_translation(placed.matrix3.as_mat3(), placed.translation.as_vec3())
    }

    /// From the render space to the file's coordinates.
    pub(crate) fn to_file(self) -> DAffine3 {
        DAffine3::from_translation(self.origin) * DAffine3::from_scale(DVec3::splat(self.scale))
    }
}

/// A mesh far from its own origin, moved to it; returns the move (`file = local + offset`).
/// f32 vertices near 10^6 subtract exactly from a centre of the same magnitude.
pub(crate) fn recentred_mesh(mut mesh: TriangleMesh) -> (TriangleMesh, DVec3) {
    let Some(bounds) = crate::bounds::bounds_of_points(mesh.positions.iter().copied()) else {
        return (mesh, DVec3::ZERO);
    };
    let bounds =
        WorldBounds { min: Vec3::from(bounds.min).as_dvec3(), max: Vec3::from(bounds.max).as_dvec3() };
    let offset = RenderSpace::around(Some(bounds)).origin;
    let shift = offset.as_vec3();
    mesh.positions.iter_mut().for_each(|p| *p -= shift);
    (mesh, shift.as_dvec3())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_scenes_far_away_or_of_unusual_size_move() {
        let near = WorldBounds { min: DVec3::splat(-1.0), max: DVec3::new(2.0, 1.0, 1.0) };
        assert_eq!(RenderSpace::around(Some(near)), RenderSpace::FILE);
        assert_eq!(RenderSpace::around(None), RenderSpace::FILE);
        let utm = WorldBounds {
            min: DVec3::new(640_000.0, 5e6, 100.0),
            max: DVec3::new(640_010.0, 5e6 + 4.0, 102.0),
        };
        let space = RenderSpace::around(Some(utm));
        assert_eq!(space, RenderSpace { origin: DVec3::new(640_005.0, 5e6 + 2.0, 101.0), scale: 1.0 });
        let huge = WorldBounds { min: DVec3::splat(-1e10), max: DVec3::splat(1e10) };
        assert_eq!(RenderSpace::around(Some(huge)).scale, 2f64.powi(35));
    }

    #[test]
    fn a_geo_referenced_translation_keeps_its_centimetres() {
        let space = RenderSpace { origin: DVec3::new(640_000.0, 5_000_000.0, 100.0), scale: 1.0 };
        let placed = DAffine3::from_translation(space.origin + DVec3::new(0.37, 0.01, -0.25));
        assert_eq!(space.transform(&placed).translation, glam::Vec3A::new(0.37, 0.01, -0.25));
    }
}
