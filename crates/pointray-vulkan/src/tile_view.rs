//! Which tiles of a streamed point set a camera needs first: those its view frustum touches,
//! the largest on screen first, then the rest by how large they would look (they still
//! cast shadows and show in reflections).

use glam::Vec3;
use pointray_kernels::Aabb;
use pointray_scene::Camera;

/// A camera's view frustum as four side planes through its position.
pub(crate) struct TileView {
    position: Vec3,
    forward: Vec3,
    /// Inward unit normals of the left, right, bottom and top planes.
    sides: [Vec3; 4],
}

impl TileView {
    /// The frustum of `camera` for an image `aspect` (width over height) wide.
    pub(crate) fn new(camera: &Camera, aspect: f32) -> Self {
        let forward = (camera.look_at - camera.position).normalize();
        let right = forward.cross(camera.up).normalize();
        let up = right.cross(forward);
        let tan_vertical = (0.5 * camera.vertical_fov_degrees.to_radians()).tan();
        let tan_horizontal = tan_vertical * aspect;
        let side = |slope: f32, axis: Vec3| (slope * forward + axis).normalize();
        Self {
            position: camera.position,
            forward,
            sides: [
                side(tan_horizontal, right),
                side(tan_horizontal, -right),
                side(tan_vertical, up),
                side(tan_vertical, -up),
            ],
        }
    }

    /// Whether `bounds` reaches into the frustum: no side plane (nor the plane through the
    /// camera facing forward) has the whole box behind it. Conservative near the frustum's
    /// edges, where a box beside two planes may count without touching the frustum.
    pub(crate) fn sees(&self, bounds: &Aabb) -> bool {
        let (min, max) = (Vec3::from(bounds.min), Vec3::from(bounds.max));
        let ahead = |normal: Vec3| {
            let farthest = Vec3::select(normal.cmpge(Vec3::ZERO), max, min);
            (farthest - self.position).dot(normal) >= 0.0
        };
        ahead(self.forward) && self.sides.iter().all(|&side| ahead(side))
    }

    /// How large `bounds` looks from the camera: its bounding radius over its distance,
    /// unbounded with the camera inside it.
    fn apparent_size(&self, center: Vec3, radius: f32) -> f32 {
        let distance = center.distance(self.position);
        if distance <= radius { f32::INFINITY } else { radius / distance }
    }

    /// The indices of `tiles` (world-space bounds, `seen` where `sees` says so) in the order
    /// they should be loaded: seen ones before unseen ones, each group by apparent size,
    /// largest first; ties by index.
    pub(crate) fn rank(&self, tiles: &[Aabb], seen: &[bool]) -> Vec<usize> {
        let keys: Vec<(bool, f32)> = tiles
            .iter()
            .zip(seen)
            .map(|(tile, &seen)| {
                let (center, radius) = sphere(tile);
                (!seen, -self.apparent_size(center, radius))
            })
            .collect();
        let mut order: Vec<usize> = (0..tiles.len()).collect();
        order.sort_by(|&a, &b| {
            keys[a].0.cmp(&keys[b].0).then(keys[a].1.total_cmp(&keys[b].1)).then(a.cmp(&b))
        });
        order
    }
}

/// The bounding sphere of a box: its centre and half its diagonal.
fn sphere(bounds: &Aabb) -> (Vec3, f32) {
    let (min, max) = (Vec3::from(bounds.min), Vec3::from(bounds.max));
    (0.5 * (min + max), 0.5 * (max - min).length())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera_looking_along_x() -> Camera {
        Camera { position: Vec3::ZERO, look_at: Vec3::X, up: Vec3::Z, vertical_fov_degrees: 60.0 }
    }

    fn unit_box_at(center: Vec3) -> Aabb {
        Aabb::cube(center, 0.5)
    }

    #[test]
    fn boxes_in_front_are_seen_and_boxes_behind_or_beside_are_not() {
        let view = TileView::new(&camera_looking_along_x(), 1.0);
        assert!(view.sees(&unit_box_at(Vec3::new(10.0, 0.0, 0.0))));
        assert!(view.sees(&unit_box_at(Vec3::new(10.0, 5.0, 5.0))), "inside the 60° cone's corner");
        assert!(!view.sees(&unit_box_at(Vec3::new(-10.0, 0.0, 0.0))), "behind");
        assert!(!view.sees(&unit_box_at(Vec3::new(10.0, 0.0, 10.0))), "above the top plane");
        assert!(!view.sees(&unit_box_at(Vec3::new(10.0, 12.0, 0.0))), "left of a square image");
        let wide = TileView::new(&camera_looking_along_x(), 3.0);
        assert!(wide.sees(&unit_box_at(Vec3::new(10.0, 12.0, 0.0))), "inside a wide image");
        assert!(view.sees(&Aabb::cube(Vec3::new(-1.0, 0.0, 0.0), 2.0)), "the camera inside");
    }

    #[test]
    fn seen_tiles_come_first_nearest_first_then_the_unseen_by_apparent_size() {
        let view = TileView::new(&camera_looking_along_x(), 1.0);
        let tiles = [
            unit_box_at(Vec3::new(-3.0, 0.0, 0.0)),  // behind, near
            unit_box_at(Vec3::new(20.0, 0.0, 0.0)),  // seen, far
            unit_box_at(Vec3::new(5.0, 0.0, 0.0)),   // seen, near
            unit_box_at(Vec3::new(-30.0, 0.0, 0.0)), // behind, far
            unit_box_at(Vec3::new(0.2, 0.0, 0.0)),   // around the camera
        ];
        let seen: Vec<bool> = tiles.iter().map(|tile| view.sees(tile)).collect();
        assert_eq!(seen, [false, true, true, false, true]);
        assert_eq!(view.rank(&tiles, &seen), vec![4, 2, 1, 0, 3]);
    }
}
