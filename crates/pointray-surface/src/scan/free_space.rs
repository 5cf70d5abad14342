//! The space a sensor's rays crossed is empty, and no patch may reach into it. A return off a
//! patch's surface, whose ray passes through the patch on its way, shows where that surface
//! ends: the patch is cut back on the side of its return that the ray crosses, so that its
//! ellipse ends where the ray passed and still reaches as far as before on the other side.
//! This keeps a sidewalk's patches from reaching over the kerb into the road's rays, and a
//! car's from floating over the ground beside it.
//!
//! Where the next line's return lies behind the patch's plane (the face of a kerb below a
//! sidewalk's edge), the patch is also cut back over that return, where the edge lies.

use glam::{Vec2, Vec3};

use crate::scan::edges::across_neighbours;
use crate::scan::lines::ScanLines;

/// A ray passes the patch in front of its return when it meets the patch's plane this many
/// standard deviations of the range noise before the return.
const NOISE_SIGMAS: f32 = 3.5;

/// A cut leaves at least this share of the support's radius on each side of its return.
const MIN_SIDE_SHARE: f32 = 0.1;

/// A cut at a step leaves the step this fraction outside the ellipse's edge, so that the
/// rounding of the stored support cannot bring it back in.
const CUT_CLEARANCE: f32 = 0.98;

/// A passing ray cuts the ellipse's edge back to this share of the way from its return to the
/// crossing. The surface's real edge lies somewhere between the two rays; an edge on the
/// passing ray itself covers the footprint around that ray, so that from the sensor the
/// surface floats over the pixels beside the return behind it (2-3 % of the pixels of real
/// 64- and 32-beam sweeps). Half the way leaves gaps where one line alone crosses a narrow
/// surface; bench/FIDELITY.md has the measurements.
const PASSING_RAY_EDGE_SHARE: f32 = 0.7;

/// An elliptical support: `radii.x` along `major`, `radii.y` along `normal × major`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipse {
    pub centre: Vec3,
    pub normal: Vec3,
    pub major: Vec3,
    pub radii: Vec2,
}

/// How far an ellipse reaches from a point inside it, on each side along each of its axes:
/// `plus.x` along `major`, `minus.x` against it, and likewise on the minor axis.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Reach {
    plus: Vec2,
    minus: Vec2,
    /// No side is cut back nearer the point than this: its own ray must meet its patch
    /// inside the stored (rounded) support, not on its edge.
    floor: Vec2,
}

impl Reach {
    /// The ellipse's centre, relative to the point, in `(major, minor)` coordinates.
    fn centre(&self) -> Vec2 {
        (self.plus - self.minus) * 0.5
    }

    fn radii(&self) -> Vec2 {
        (self.plus + self.minus) * 0.5
    }

    /// The smallest cut of one side's reach, on the axis along which `crossing` (relative to
    /// the point) lies furthest out toward that side's edge, that brings that edge back to
    /// `PASSING_RAY_EDGE_SHARE` of the way to it. The point itself stays inside.
    fn exclude(&mut self, crossing: Vec2) {
        let toward = Vec2::select(crossing.cmpge(Vec2::ZERO), self.plus, self.minus);
        let out = (crossing / toward).abs();
        let (along, across) = if out.x >= out.y { (0, 1) } else { (1, 0) };
        let across_share = ((crossing - self.centre()) / self.radii())[across].clamp(-1.0, 1.0);
        // The ellipse's half-width on the cut axis at the crossing's height across it.
        let width = (1.0 - across_share * across_share).sqrt();
        let floor = self.floor[along];
        let target = PASSING_RAY_EDGE_SHARE * crossing[along].abs();
        let (side, other) = if crossing[along] >= 0.0 {
            (&mut self.plus[along], self.minus[along])
        } else {
            (&mut self.minus[along], self.plus[along])
        };
        // centre + radius × width = target, with centre and radius both depending on the side.
        let cut = (2.0 * target + other * (1.0 - width)) / (1.0 + width);
        *side = cut.clamp(floor.min(*side), *side);
    }

    /// Limits the reach on the side of `direction` (relative to the point) along the axis it
    /// mostly follows to `limit` (`CUT_CLEARANCE` of it), keeping the point inside.
    fn limit_toward(&mut self, direction: Vec2, limit: f32) {
        let along = if direction.x.abs() >= direction.y.abs() { 0 } else { 1 };
        let floor = self.floor[along];
        let side = if direction[along] >= 0.0 { &mut self.plus[along] } else { &mut self.minus[along] };
        *side = (CUT_CLEARANCE * limit).clamp(floor.min(*side), *side);
    }
}

impl Ellipse {
    /// The ellipse of point `i`'s patch cut back by the rays of the returns around it, its
    /// station's and the nearest other stations', that pass through it in front of their
    /// return (another sweep of a map, or a multi-block head's other block, saw through
    /// there too), skipping those of `members` (sorted) within
    /// its reach and any other return that lies on its plane as members do (within `max_rise`
    /// of it). Members beyond its reach count as any return: a narrow object's plane may take
    /// in a wall far behind it, whose rays must still cut it.
    pub fn cut_by_passing_rays(
        self,
        points: &[Vec3],
        scan: &ScanLines,
        i: usize,
        members: &[u32],
        max_rise: f32,
    ) -> Self {
        let margin = NOISE_SIGMAS * scan.range_noise;
        let range = self.centre.distance(scan.sensor[i]).max(f32::MIN_POSITIVE);
        let angle = (self.radii.x / range).min(1.0);
        let point = points[i];
        let mut reach = self.reach_from(point);
        let others = scan.other_stations_returns_near(self.centre, self.radii.x, scan.station_of(i));
        for j in scan.returns_near_ray(i, angle).into_iter().chain(others) {
            let (origin, end) = (scan.sensor[j as usize], points[j as usize]);
            let member = members.binary_search(&j).is_ok() && self.reaches(end);
            if member || self.holds(origin, end, margin, max_rise) {
                continue;
            }
            let current = self.with_reach(point, reach);
            if let Some(crossing) = current.crossing(origin, end, margin) {
                reach.exclude(crossing + current.local(current.centre - point));
            }
        }
        self.with_reach(point, reach).with_major_axis_longest()
    }

    /// The ellipse of point `i`'s patch cut back where it steps down: where the next line's
    /// return lies behind its plane, beyond the noise (the face of a kerb below a sidewalk's
    /// edge), the sensor saw that return's surface between the two rays, and the edge lies
    /// about over that return.
    pub fn cut_at_steps(self, points: &[Vec3], scan: &ScanLines, i: usize) -> Self {
        let margin = NOISE_SIGMAS * scan.range_noise;
        let point = points[i];
        let mut reach = self.reach_from(point);
        for j in across_neighbours(scan, i) {
            let (origin, end) = (scan.sensor[j as usize], points[j as usize]);
            if let Some(hit) = self.hit_before(origin, end, margin) {
                // The ray's hit on the plane tells the side; the return's foot on the plane
                // where the step lies. Noise may put the foot on the other side.
                let toward = self.local(hit - point);
                let foot = self.local(end - point);
                reach.limit_toward(toward, foot.dot(toward.normalize_or_zero()).max(0.0));
            }
        }
        self.with_reach(point, reach).with_major_axis_longest()
    }

    /// Its reach on each side from `point` (inside it), along its axes.
    fn reach_from(&self, point: Vec3) -> Reach {
        let offset = self.local(point - self.centre);
        Reach { plus: self.radii - offset, minus: self.radii + offset, floor: self.radii * MIN_SIDE_SHARE }
    }

    /// The ellipse of the same plane and axes that reaches `reach` from `point`.
    fn with_reach(&self, point: Vec3, reach: Reach) -> Self {
        let centre = reach.centre();
        let minor = self.normal.cross(self.major);
        Self { centre: point + self.major * centre.x + minor * centre.y, radii: reach.radii(), ..*self }
    }

    /// `offset` (along the plane) in `(major, minor)` coordinates.
    fn local(&self, offset: Vec3) -> Vec2 {
        Vec2::new(offset.dot(self.major), offset.dot(self.normal.cross(self.major)))
    }

    /// Where the segment from `origin` to `end` meets the plane, when it does so more than
    /// `margin` before `end`: the return at `end` lies behind the plane, beyond its noise.
    fn hit_before(&self, origin: Vec3, end: Vec3, margin: f32) -> Option<Vec3> {
        let (before, after) = ((origin - self.centre).dot(self.normal), (end - self.centre).dot(self.normal));
        let fraction = before / (before - after);
        let behind = before * after < 0.0 && (1.0 - fraction) * origin.distance(end) > margin;
        behind.then(|| origin + (end - origin) * fraction)
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
        let local = self.local(origin + direction * t - self.centre);
        ((local / self.radii).length_squared() < 1.0).then_some(local)
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
        let mut reach = ellipse.reach_from(Vec3::ZERO);
        reach.exclude(crossing);
        // Cut on the crossing's side only: the other side reaches as far as before.
        assert_eq!(reach.minus, Vec2::new(2.0, 1.0));
        assert!((reach.plus - Vec2::new(1.5 * PASSING_RAY_EDGE_SHARE, 1.0)).length() < 1e-6, "{reach:?}");
        let cut = ellipse.with_reach(Vec3::ZERO, reach);
        assert!(
            (cut.centre - Vec3::new((1.5 * PASSING_RAY_EDGE_SHARE - 2.0) * 0.5, 0.0, 0.0)).length() < 1e-6
        );
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
    fn a_crossing_off_the_axes_moves_the_edge_back_between_the_rays() {
        let ellipse = ellipse_two_by_one();
        let mut reach = ellipse.reach_from(Vec3::ZERO);
        let crossing = Vec2::new(0.3, 0.8);
        reach.exclude(crossing);
        let within = |offset: Vec2| ((offset - reach.centre()) / reach.radii()).length_squared();
        // Cut on the minor axis, which the crossing lies furthest out along.
        let edge = Vec2::new(crossing.x, crossing.y * PASSING_RAY_EDGE_SHARE);
        assert!((within(edge) - 1.0).abs() < 1e-4, "{reach:?}");
        assert!(within(crossing) > 1.2, "{reach:?}");
        assert_eq!(reach.radii().x, 2.0);
    }

    #[test]
    fn a_cut_beside_the_point_leaves_the_point_inside() {
        let ellipse = ellipse_two_by_one();
        let point = Vec3::new(0.5, 0.2, 0.0);
        let mut reach = ellipse.reach_from(point);
        let crossings = [Vec2::new(-0.01, 0.0), Vec2::new(0.0, 0.01)];
        for crossing in crossings {
            reach.exclude(crossing);
        }
        let cut = ellipse.with_reach(point, reach);
        let within = |offset: Vec2| ((offset - cut.local(cut.centre - point)) / cut.radii).length_squared();
        assert!(within(Vec2::ZERO) < 1.0, "{cut:?}");
        for crossing in crossings {
            assert!(within(crossing) >= 1.0, "{crossing} in {cut:?}");
        }
        // The far side keeps its reach: the ellipse still ends 1.5 beyond the point.
        assert!((cut.centre.x + cut.radii.x - 2.0).abs() < 1e-5, "{cut:?}");
    }

    #[test]
    fn the_longer_radius_stays_the_major_one() {
        let ellipse = ellipse_two_by_one();
        let mut reach = ellipse.reach_from(Vec3::ZERO);
        reach.exclude(Vec2::new(0.5, 0.0));
        reach.exclude(Vec2::new(-0.5, 0.0));
        let ellipse = ellipse.with_reach(Vec3::ZERO, reach).with_major_axis_longest();
        assert_eq!(ellipse.radii, Vec2::new(1.0, 0.5 * PASSING_RAY_EDGE_SHARE));
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
