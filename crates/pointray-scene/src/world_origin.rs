//! The render frame: scenes are loaded in f64 and recentred on their objects before anything
//! goes to f32. Geo-referenced scenes sit 10^5 to 10^7 units from the origin, where an f32 keeps
//! only decimetres to metres: rays, hits and BVH boxes there come out scattered or missing.
//! Recentred, the renderers see the same numbers as for the scene at the origin.

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
    let local = crate::bounds::bounds_of_points(geometry.local_points())?;
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

/// Where the render frame's origin goes in file coordinates: the objects' centre when they lie
/// far from the file's origin for their size, else the file's origin, so that a scene near the
/// origin renders exactly as written.
pub(crate) fn world_origin(bounds: Option<WorldBounds>) -> DVec3 {
    match bounds {
        Some(bounds) if bounds.center().length() > RECENTRE_BEYOND_SIZES * bounds.diagonal() => {
            bounds.center()
        }
        _ => DVec3::ZERO,
    }
}

/// `local_to_world` seen from the render frame at `origin`, in f32.
pub(crate) fn render_transform(local_to_world: &DAffine3, origin: DVec3) -> Affine3A {
    let recentred = DAffine3::from_translation(-origin) * *local_to_world;
    Affine3A::from_mat3_translation(recentred.matrix3.as_mat3(), recentred.translation.as_vec3())
}

/// A mesh far from its own origin, moved to it; returns the move (`file = local + offset`).
/// f32 vertices near 10^6 subtract exactly from a centre of the same magnitude.
pub(crate) fn recentred_mesh(mut mesh: TriangleMesh) -> (TriangleMesh, DVec3) {
    let Some(bounds) = crate::bounds::bounds_of_points(mesh.positions.iter().copied()) else {
        return (mesh, DVec3::ZERO);
    };
    let bounds =
        WorldBounds { min: Vec3::from(bounds.min).as_dvec3(), max: Vec3::from(bounds.max).as_dvec3() };
    let offset = world_origin(Some(bounds));
    let shift = offset.as_vec3();
    mesh.positions.iter_mut().for_each(|p| *p -= shift);
    (mesh, shift.as_dvec3())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_scenes_away_from_the_origin_move() {
        let near = WorldBounds { min: DVec3::splat(-1.0), max: DVec3::new(2.0, 1.0, 1.0) };
        assert_eq!(world_origin(Some(near)), DVec3::ZERO);
        let utm = WorldBounds {
            min: DVec3::new(640_000.0, 5e6, 100.0),
            max: DVec3::new(640_010.0, 5e6 + 4.0, 102.0),
        };
        assert_eq!(world_origin(Some(utm)), DVec3::new(640_005.0, 5e6 + 2.0, 101.0));
        assert_eq!(world_origin(None), DVec3::ZERO);
    }

    #[test]
    fn a_geo_referenced_translation_keeps_its_centimetres() {
        let origin = DVec3::new(640_000.0, 5_000_000.0, 100.0);
        let placed = DAffine3::from_translation(origin + DVec3::new(0.37, 0.01, -0.25));
        let transform = render_transform(&placed, origin);
        assert_eq!(transform.translation, glam::Vec3A::new(0.37, 0.01, -0.25));
    }
}
