//! Where a point's neighbourhood spreads out of its plane by more than the range noise, a
//! step may lie in it: a kerb, whose road is seen by the lines below the point's and whose
//! sidewalk by the lines above, with the kerb's face seen by the point's line alone. Any two
//! lines span a plane (near a point, lines are nearly parallel), so a plane through the point
//! ramps from one level to the other as readily as it follows either. Here each level is the
//! plane of the two lines on one side, and the point lies on one of them or on the face
//! between.

use glam::{DMat3, DVec3, Vec3};

use crate::normals::{neighbourhood_covariance, smallest_eigenvector};
use crate::scan::lines::ScanLines;
use crate::scan::neighborhood::{Candidates, MIN_NOISE_SHARE, NOISE_SIGMAS, fitted_normal};

/// At most this share of a level's returns may lie off it, beyond the noise (a dropout's
/// neighbour, a leaf): more, and the two lines do not lie on one plane.
const MAX_OFF_LEVEL: f32 = 0.1;

/// A level's two lines must each hold this many returns of the window.
const MIN_LINE_RETURNS: usize = 3;

/// The levels of a step face the same way, to within about 25°.
const MIN_STEP_ALIGNMENT: f32 = 0.9;

/// What the levels beside a point say about it.
#[derive(Clone, Debug, PartialEq)]
pub enum LevelFit {
    /// The point lies on a level: the unit normal (not oriented) of the plane that fits the
    /// window's returns on it.
    On(Vec3),
    /// It lies between a level below and a level above that face the same way: on the face of
    /// the step between them, seen by its own line alone.
    Between(StepFace),
    /// No level beside it says either.
    Unknown,
}

/// The face of a step around a point between two levels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepFace {
    /// The unit normal of the levels, from the one below the point toward the one above.
    pub up: Vec3,
    /// How far the level below and the level above lie from the point, along `up`.
    pub below: f32,
    pub above: f32,
    /// The direction of the face's returns on the point's line, when three or more lie
    /// between the levels: along a line returns lie closer than the range noise, so only the
    /// whole run gives its direction.
    pub along: Option<Vec3>,
}

/// The plane of two adjacent lines: its centroid, unit normal and returns.
struct Level {
    centre: Vec3,
    normal: Vec3,
    members: Vec<u32>,
}

impl Level {
    /// How far `p` lies from the plane, in units of the `tolerance` there: within the noise
    /// of it up to 1.
    fn misfit(&self, p: Vec3, tolerance: &impl Fn(Vec3, Vec3) -> f32) -> f32 {
        (p - self.centre).dot(self.normal).abs() / tolerance(p, self.normal)
    }
}

/// The levels of the two lines below point `i`'s and of the two above, among its
/// `candidates`' window, and where the point lies against them.
pub fn level_fit(points: &[Vec3], scan: &ScanLines, i: usize, candidates: &Candidates) -> LevelFit {
    let tolerance = |p: Vec3, normal: Vec3| {
        let ray = (p - scan.sensor[i]).normalize_or_zero();
        NOISE_SIGMAS * scan.range_noise * ray.dot(normal).abs().max(MIN_NOISE_SHARE)
    };
    let on = |level: &Level, j: u32| level.misfit(points[j as usize], &tolerance) <= 1.0;
    let line = &scan.lines[scan.line_of[i] as usize];
    let side = |first: Option<u32>, up: bool| {
        let second =
            first.and_then(|l| if up { scan.lines[l as usize].above } else { scan.lines[l as usize].below });
        level_of(points, scan, candidates, [first?, second?], &tolerance)
    };
    let levels = [side(line.below, false), side(line.above, true)];
    let misfit = |level: &Level| level.misfit(points[i], &tolerance);
    let mut on_levels: Vec<&Level> = levels.iter().flatten().filter(|level| misfit(level) <= 1.0).collect();
    if let [a, b] = on_levels[..]
        && a.normal.dot(b.normal).abs() < MIN_STEP_ALIGNMENT
    {
        // At a crease (a wall's foot) the point lies within the noise of both planes.
        on_levels = vec![if misfit(a) <= misfit(b) { a } else { b }];
    }
    if !on_levels.is_empty() {
        let on_any = |j: &u32| on_levels.iter().any(|level| on(level, *j));
        let members: Vec<u32> = candidates.window.iter().copied().filter(on_any).collect();
        return LevelFit::On(fitted_normal(points, i, candidates, &members));
    }
    match levels {
        [Some(below), Some(above)] if steps_between(&below, &above, points[i]) => {
            let off_levels = |j: &u32| !on(&below, *j) && !on(&above, *j);
            LevelFit::Between(step_face(points, scan, i, candidates, (&below, &above), off_levels))
        }
        _ => LevelFit::Unknown,
    }
}

/// The face of the step between `levels` (below, above) at point `i`, with the direction of
/// the returns of its line that lie between them (`off_levels`, and on the inner side of each).
fn step_face(
    points: &[Vec3],
    scan: &ScanLines,
    i: usize,
    candidates: &Candidates,
    (below, above): (&Level, &Level),
    off_levels: impl Fn(&u32) -> bool,
) -> StepFace {
    let up = below.normal * (points[i] - below.centre).dot(below.normal).signum();
    let heights = |p: Vec3| ((p - below.centre).dot(up), (above.centre - p).dot(up));
    let own = scan.line_of[i];
    let on_face = |j: &u32| {
        let (over_below, under_above) = heights(points[*j as usize]);
        scan.line_of[*j as usize] == own && off_levels(j) && over_below > 0.0 && under_above > 0.0
    };
    let face: Vec<u32> = candidates.window.iter().copied().filter(on_face).chain([i as u32]).collect();
    let along = if face.len() >= 3 { principal_direction(points, &face) } else { None };
    let (below, above) = heights(points[i]);
    StepFace { up, below, above, along }
}

/// The plane of the window's returns on `lines`, when each holds `MIN_LINE_RETURNS` and all
/// but `MAX_OFF_LEVEL` of them lie within the noise of it.
fn level_of(
    points: &[Vec3],
    scan: &ScanLines,
    candidates: &Candidates,
    lines: [u32; 2],
    tolerance: &impl Fn(Vec3, Vec3) -> f32,
) -> Option<Level> {
    let members: Vec<u32> =
        candidates.window.iter().copied().filter(|&j| lines.contains(&scan.line_of[j as usize])).collect();
    let on_line = |l: u32| members.iter().filter(|&&j| scan.line_of[j as usize] == l).count();
    if lines.iter().any(|&l| on_line(l) < MIN_LINE_RETURNS) {
        return None;
    }
    let centre = members.iter().map(|&j| points[j as usize].as_dvec3()).sum::<DVec3>() / members.len() as f64;
    let normal = smallest_eigenvector(covariance(points, &members)).as_vec3().try_normalize()?;
    let level = Level { centre: centre.as_vec3(), normal, members };
    let off = level.members.iter().filter(|&&j| level.misfit(points[j as usize], tolerance) > 1.0);
    (off.count() as f32 <= MAX_OFF_LEVEL * level.members.len() as f32).then_some(level)
}

/// The direction along which `members` (one or more) spread the most.
fn principal_direction(points: &[Vec3], members: &[u32]) -> Option<Vec3> {
    let spread = covariance(points, members);
    // The largest eigenvector of the spread is the smallest of its complement to its trace.
    let trace = spread.x_axis.x + spread.y_axis.y + spread.z_axis.z;
    smallest_eigenvector(DMat3::from_diagonal(DVec3::splat(trace)) - spread).as_vec3().try_normalize()
}

/// The covariance of `members` (one or more).
fn covariance(points: &[Vec3], members: &[u32]) -> DMat3 {
    neighbourhood_covariance(points, members[0] as usize, &members[1..])
}

/// Whether `p` lies between two levels that face the same way: on a step's face, not beside
/// the crease of two planes or off two unrelated ones.
fn steps_between(below: &Level, above: &Level, p: Vec3) -> bool {
    let alignment = below.normal.dot(above.normal);
    let above_normal = above.normal * alignment.signum();
    alignment.abs() >= MIN_STEP_ALIGNMENT
        && (p - below.centre).dot(below.normal).signum() != (p - above.centre).dot(above_normal).signum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn level(height: f32, normal: Vec3) -> Level {
        Level { centre: Vec3::new(0.0, 0.0, height), normal, members: Vec::new() }
    }

    #[test]
    fn a_point_between_two_levels_facing_one_way_is_on_a_step() {
        let (road, sidewalk) = (level(0.0, Vec3::Z), level(0.15, -Vec3::Z));
        assert!(steps_between(&road, &sidewalk, Vec3::new(1.0, 5.0, 0.07)));
        assert!(!steps_between(&road, &sidewalk, Vec3::new(1.0, 6.0, 0.3)), "above both");
        let wall = Level { centre: Vec3::new(0.0, 9.0, 0.0), normal: Vec3::Y, members: Vec::new() };
        assert!(!steps_between(&road, &wall, Vec3::new(1.0, 8.9, 0.1)), "beside a crease");
    }

    #[test]
    fn the_principal_direction_follows_the_longest_spread() {
        let points: Vec<Vec3> =
            (0..9).map(|i| Vec3::new(i as f32 * 0.1, 5.0 + 0.01 * (i % 2) as f32, 0.07)).collect();
        let members: Vec<u32> = (0..9).collect();
        let direction = principal_direction(&points, &members).unwrap();
        assert!(direction.x.abs() > 0.99, "{direction}");
    }
}
