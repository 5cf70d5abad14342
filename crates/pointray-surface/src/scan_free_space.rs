//! The space a sensor's rays crossed is empty, and no patch may reach into it. A return off a
//! patch's surface, whose ray passes through the patch on its way, shows where that surface
//! ends: the patch is cut back on the axis the ray crosses, so that its ellipse ends where the
//! ray passed. This keeps a sidewalk's patches from reaching over the kerb into the road's
//! rays, and a car's from floating over the ground beside it.

use glam::{Vec2, Vec3};

use crate::scan_lines::ScanLines;

/// A ray passes the patch in front of its return when it meets the patch's plane this many
/// standard deviations of the range noise before the return.
const NOISE_SIGMAS: f32 = 3.5;

/// A cut leaves the crossing this fraction outside the ellipse's edge, so that the rounding of
/// the stored support cannot bring it back in.
const CUT_CLEARANCE: f32 = 0.98;

/// An elliptical support: `radii.x` along `major`, `radii.y` along `normal × major`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipse {
    pub centre: Vec3,
    pub normal: Vec3,
    pub major: Vec3,
    pub radii: Vec2,
}

impl Ellipse {
    /// The ellipse of point `i`'s patch cut back by the rays of the returns around it that
    /// pass through it in front of their return, skipping those of `members` (sorted) within
    /// its reach and any other return that lies on its plane as members do (within `max_rise`
    /// of it). Members beyond its reach count as any return: a narrow object's plane may take
    /// in a wall far behind it, whose rays must still cut it.
    pub fn cut_by_passing_rays(
        mut self,
        points: &[Vec3],
        scan: &ScanLines,
        i: usize,
        members: &[u32],
        max_rise: f32,
    ) -> Self {
        let margin = NOISE_SIGMAS * scan.range_noise;
        let range = self.centre.distance(scan.sensor[i]).max(f32::MIN_POSITIVE);
        let angle = (self.radii.x / range).min(1.0);
        for j in scan.returns_near_ray(i, angle) {
            let (origin, end) = (scan.sensor[j as usize], points[j as usize]);
            let member = members.binary_search(&j).is_ok() && self.reaches(end);
            if member || self.holds(origin, end, margin, max_rise) {
                continue;
            }
            if let Some(crossing) = self.crossing(origin, end, margin) {
                self.shrink_to_exclude(crossing);
            }
        }
        self.with_major_axis_longest()
    }

    /// Whether the return at `end` lies on the ellipse's plane as a member would: within the
    /// ellipse's reach, rising out of the plane at most `max_rise` over its distance along it,
    /// once the range noise is allowed. Farther out a gentle slope may still hide metres: a
    /// wall far behind a pole's patch must cut it.
    fn holds(&self, origin: Vec3, end: Vec3, margin: f32, max_rise: f32) -> bool {
        let offset = end - self.centre;
        let noise = margin * (end - origin).normalize_or_zero().dot(self.normal).abs();
        let rise = (offset.dot(self.normal).abs() - noise).max(0.0);
        self.reaches(end) && rise <= max_rise * self.run_to(end)
    }

    /// Whether `point` lies within the ellipse's larger radius of its centre along its plane.
    fn reaches(&self, point: Vec3) -> bool {
        self.run_to(point) <= self.radii.x
    }

    /// The distance from the centre to `point` along the plane.
    fn run_to(&self, point: Vec3) -> f32 {
        let offset = point - self.centre;
        (offset - offset.dot(self.normal) * self.normal).length()
    }

    /// Where the segment from `origin` to `end`, stopped `margin` short of `end`, passes
    /// through the ellipse: local `(u, v)` coordinates.
    fn crossing(&self, origin: Vec3, end: Vec3, margin: f32) -> Option<Vec2> {
        let to_end = end - origin;
        let range = to_end.length();
        let direction = to_end / range;
        let facing = direction.dot(self.normal);
        if facing.abs() < 1e-6 {
            return None;
        }
        let t = (self.centre - origin).dot(self.normal) / facing;
        if t <= 0.0 || t >= range - margin {
            return None;
        }
        let offset = origin + direction * t - self.centre;
        let local = Vec2::new(offset.dot(self.major), offset.dot(self.normal.cross(self.major)));
        ((local / self.radii).length_squared() < 1.0).then_some(local)
    }

    /// The smallest change of one radius, the one `crossing` lies furthest along relative to
    /// it, that leaves `crossing` just outside the ellipse's edge (`CUT_CLEARANCE`).
    fn shrink_to_exclude(&mut self, crossing: Vec2) {
        let [u, v] = (crossing / self.radii).to_array().map(|c| c * c);
        let edge = |along: f32, other: f32| {
            (CUT_CLEARANCE * along.abs() / (1.0 - other).sqrt()).max(f32::MIN_POSITIVE)
        };
        if u >= v {
            self.radii.x = edge(crossing.x, v);
        } else {
            self.radii.y = edge(crossing.y, u);
        }
    }

    fn with_major_axis_longest(self) -> Self {
        if self.radii.x >= self.radii.y {
            return self;
        }
        Self { major: self.normal.cross(self.major), radii: Vec2::new(self.radii.y, self.radii.x), ..self }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ellipse_two_by_one() -> Ellipse {
        Ellipse { centre: Vec3::ZERO, normal: Vec3::Z, major: Vec3::X, radii: Vec2::new(2.0, 1.0) }
    }

    #[test]
    fn a_ray_through_the_ellipse_to_a_return_behind_it_cuts_it_back() {
        let ellipse = ellipse_two_by_one();
        let crossing = ellipse.crossing(Vec3::new(1.5, 0.0, 5.0), Vec3::new(1.5, 0.0, -1.0), 0.05).unwrap();
        assert!((crossing - Vec2::new(1.5, 0.0)).length() < 1e-6);
        let mut cut = ellipse;
        cut.shrink_to_exclude(crossing);
        assert!((cut.radii - Vec2::new(1.5 * CUT_CLEARANCE, 1.0)).length() < 1e-6, "{cut:?}");
    }

    #[test]
    fn rays_that_end_on_the_plane_outside_or_before_it_cut_nothing() {
        let ellipse = ellipse_two_by_one();
        // Its return lies on the plane, within the margin.
        assert_eq!(ellipse.crossing(Vec3::new(0.5, 0.0, 5.0), Vec3::new(0.5, 0.0, -0.01), 0.05), None);
        // It passes outside the ellipse.
        assert_eq!(ellipse.crossing(Vec3::new(0.0, 1.5, 5.0), Vec3::new(0.0, 1.5, -1.0), 0.05), None);
        // It ends in front of the plane.
        assert_eq!(ellipse.crossing(Vec3::new(0.5, 0.0, 5.0), Vec3::new(0.5, 0.0, 1.0), 0.05), None);
        // It runs parallel to it.
        assert_eq!(ellipse.crossing(Vec3::new(-5.0, 0.0, 0.0), Vec3::new(5.0, 0.0, 0.0), 0.05), None);
    }

    #[test]
    fn a_crossing_off_the_axes_moves_the_edge_just_past_it() {
        let mut ellipse = ellipse_two_by_one();
        let crossing = Vec2::new(0.3, 0.8);
        ellipse.shrink_to_exclude(crossing);
        let outside = (crossing / ellipse.radii).length_squared();
        assert!(outside > 1.0 && outside < 1.1, "{ellipse:?}");
        assert_eq!(ellipse.radii.x, 2.0);
    }

    #[test]
    fn the_longer_radius_stays_the_major_one() {
        let mut ellipse = ellipse_two_by_one();
        ellipse.shrink_to_exclude(Vec2::new(0.5, 0.0));
        let ellipse = ellipse.with_major_axis_longest();
        assert_eq!(ellipse.radii, Vec2::new(1.0, 0.5 * CUT_CLEARANCE));
        assert!((ellipse.major - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn a_return_off_the_plane_by_more_than_the_rise_does_not_hold() {
        let ellipse = ellipse_two_by_one();
        let sensor = Vec3::new(0.0, 0.0, 10.0);
        assert!(ellipse.holds(sensor, Vec3::new(1.0, 0.0, 0.05), 0.0, 0.1));
        assert!(!ellipse.holds(sensor, Vec3::new(1.0, 0.0, -0.2), 0.0, 0.1));
        // Beyond the ellipse's reach a gentle slope does not hold.
        assert!(!ellipse.holds(sensor, Vec3::new(30.0, 0.0, -1.0), 0.0, 0.1));
    }
}
