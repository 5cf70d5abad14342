//! A point's neighbourhood in a LiDAR scan: the returns around it on its own scan line and on
//! the two lines above and below, so that no support comes from its own line alone; then only
//! those that agree with one surface through the point.

use glam::{DMat3, DVec3, Vec3};

use crate::normals::smallest_eigenvector;
use crate::scan::lines::{ScanLine, ScanLines};
use crate::scan::plane_vote::PlaneVote;

/// Returns on the point's own line that seed the planes tried: this many steps away on each
/// side. Along a line returns lie closer together than the range noise, so the far one gives
/// the line's direction; the near ones keep a plane when the far one lies past an edge.
const SEED_STEPS: [usize; 3] = [1, 2, 8];

/// The neighbourhood spans this many azimuth steps on each side, on every line: at least
/// `MIN_WINDOW` (a plane's normal averages the range noise of its returns, so it needs many),
/// and about as far along the lines as the second line lies across them, up to `MAX_WINDOW`.
const MIN_WINDOW: usize = 4;
const MAX_WINDOW: usize = 16;

/// A neighbour belongs to the point's surface when the segment to it rises at most this
/// steeply out of the point's tangent plane (about 6°): gently curved bodies stay in, the foot
/// of a wall and the range jump from a car's edge to the wall behind it do not. Looser, a plane
/// tilted halfway between the ground and a wall would take in the returns of both.
pub(crate) const MAX_RISE: f32 = 0.1;

/// A neighbour may lie this many standard deviations of the scan's range noise further out
/// of the plane than `MAX_RISE` allows, the noise projected on the plane's normal: along the
/// ray it moves a return fully out of a wall seen face-on, and hardly out of the road.
pub(crate) const NOISE_SIGMAS: f32 = 3.5;

/// The sensor sees a road nearly edge-on, so its range noise moves returns along the road
/// rather than out of it; but no real surface is flatter than a fraction of the noise, so a
/// plane is allowed at least this share of it.
pub(crate) const MIN_NOISE_SHARE: f32 = 0.25;

/// Returns on other lines count only this many azimuth steps of the point's own line away
/// from it when they seed a plane: where a line has no return near the point's azimuth (out of
/// range, or a dropout), its nearest return in azimuth lies elsewhere in the scene.
const SEED_AZIMUTH_STEPS: f32 = 3.0;

/// A point's neighbourhood: the indices that agree on one surface (sorted), and the unit
/// normal of the plane that fits them (not oriented). `crosses_lines` tells whether any of
/// them lies on another line.
#[derive(Clone, Debug, PartialEq)]
pub struct ScanNeighborhood {
    pub members: Vec<u32>,
    pub normal: Vec3,
    pub crosses_lines: bool,
}

/// The returns around point `i`: `window` contains every return within the window of azimuth
/// steps on its own line and the nearby lines; `along` and `across` are the few that seed the
/// planes tried (`SEED_STEPS` along its line, the two returns bracketing its azimuth on each
/// nearby line).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Candidates {
    pub window: Vec<u32>,
    pub along: Vec<u32>,
    pub across: Vec<u32>,
}

impl ScanNeighborhood {
    /// How far the point and its members spread out of their plane (the root mean square of
    /// their distances to it, about their mean) in units of the range noise projected on its
    /// normal (at least `MIN_NOISE_SHARE` of it): about 1 where the plane is their surface,
    /// more where it ramps over a step or chords a curve.
    pub fn spread_over_noise(&self, points: &[Vec3], scan: &ScanLines, i: usize) -> f32 {
        let positions = || self.members.iter().map(|&j| points[j as usize]).chain([points[i]]);
        let count = self.members.len() as f32 + 1.0;
        let mean = positions().sum::<Vec3>() / count;
        let squares: f32 = positions().map(|p| (p - mean).dot(self.normal).powi(2)).sum();
        let ray = (points[i] - scan.sensor[i]).normalize_or_zero();
        let noise = scan.range_noise * ray.dot(self.normal).abs().max(MIN_NOISE_SHARE);
        (squares / count).sqrt() / noise
    }
}

/// The unit normal (not oriented) of the plane that fits point `i` and `members` among its
/// `candidates`, weighted as `agreeing_neighborhood` weighs them.
pub fn fitted_normal(points: &[Vec3], i: usize, candidates: &Candidates, members: &[u32]) -> Vec3 {
    plane_normal(points, i, members, nearest_across(points, i, candidates))
}

/// The distance from point `i` to the nearest of the seeds on other lines, 0 when there is
/// none: the scale below which returns lie closer than the lines do.
fn nearest_across(points: &[Vec3], i: usize, candidates: &Candidates) -> f32 {
    let scale = candidates
        .across
        .iter()
        .map(|&j| points[j as usize].distance(points[i]))
        .fold(f32::INFINITY, f32::min);
    if scale.is_finite() { scale } else { 0.0 }
}

/// The candidates of point `i`.
pub fn candidates(scan: &ScanLines, i: usize) -> Candidates {
    let line = &scan.lines[scan.line_of[i] as usize];
    let position = position_on_line(scan, line, i);
    let step = azimuth_step_at(scan, line, position);
    let azimuth = scan.azimuth[i];
    let window = window_steps(scan, i, step);
    let reach = window as f32 * step;
    let mut found = Candidates::default();
    let own = line.members[position.saturating_sub(window)..(position + window + 1).min(line.members.len())]
        .iter()
        .copied()
        .filter(|&j| j as usize != i);
    found.window.extend(own);
    found.along.extend(
        SEED_STEPS
            .iter()
            .flat_map(|&s| [position.checked_sub(s), Some(position + s)])
            .flatten()
            .filter_map(|at| line.members.get(at).copied()),
    );
    let seed_reach = SEED_AZIMUTH_STEPS * step;
    for other in scan.nearby_lines(i) {
        let first = other.members.partition_point(|&m| scan.azimuth[m as usize] < azimuth - reach);
        let within =
            other.members[first..].iter().take_while(|&&m| scan.azimuth[m as usize] <= azimuth + reach);
        found.window.extend(within);
        let bracketing = bracketing(other, scan, azimuth)
            .filter(|&j| (scan.azimuth[j as usize] - azimuth).abs() <= seed_reach);
        found.across.extend(bracketing);
    }
    found
}

/// Where point `i` stands among its line's members.
fn position_on_line(scan: &ScanLines, line: &ScanLine, i: usize) -> usize {
    let position = line.members.partition_point(|&m| scan.azimuth[m as usize] < scan.azimuth[i]);
    (position..line.members.len()).find(|&at| line.members[at] as usize == i).unwrap_or(position)
}

/// The azimuth step beside the member at `position`: the wider gap to its neighbours.
fn azimuth_step_at(scan: &ScanLines, line: &ScanLine, position: usize) -> f32 {
    let azimuth = scan.azimuth[line.members[position] as usize];
    let beside = [position.checked_sub(1), Some(position + 1)].into_iter().flatten();
    let step = beside
        .filter_map(|at| line.members.get(at))
        .map(|&j| (scan.azimuth[j as usize] - azimuth).abs())
        .fold(0.0f32, f32::max);
    step.max(1e-4)
}

/// Steps of the window on each side: as many as span the angle to the second line over, so
/// that the neighbourhood is about as wide along the lines as across them.
fn window_steps(scan: &ScanLines, i: usize, step: f32) -> usize {
    let across = scan.beam_spacing(i).unwrap_or(0.0) * 2.0;
    ((across / step).round() as usize).clamp(MIN_WINDOW, MAX_WINDOW)
}

/// The members of `line` just before and after `azimuth`.
fn bracketing<'a>(line: &'a ScanLine, scan: &ScanLines, azimuth: f32) -> impl Iterator<Item = u32> + 'a {
    let at = line.members.partition_point(|&m| scan.azimuth[m as usize] < azimuth);
    [at.checked_sub(1), Some(at)].into_iter().flatten().filter_map(|k| line.members.get(k).copied())
}

/// The neighbourhood of point `i` among `candidates`: of the planes through the point, one
/// seed along its line and one across, the one that most of the window's returns lie near (a
/// small RANSAC: a wall's returns must not tilt the ground at its foot); then the window's
/// returns that agree with it, and the plane that fits them. Also the normal of the plane whose
/// agreeing returns are the members, from which `neighborhood_agreeing_with` finds them again
/// without the vote.
pub fn agreeing_neighborhood(
    points: &[Vec3],
    scan: &ScanLines,
    i: usize,
    candidates: &Candidates,
) -> (ScanNeighborhood, Vec3) {
    let offset = |j: u32| points[j as usize] - points[i];
    let scale = nearest_across(points, i, candidates);
    let vote = plane_vote(points, scan, i, candidates, scale);
    let along: Vec<Vec3> = candidates.along.iter().map(|&j| offset(j)).collect();
    let across: Vec<Vec3> = candidates.across.iter().map(|&j| offset(j)).collect();
    let mut best: Option<(Vec3, f32)> = None;
    for normal in plane_hypotheses(&along, &across) {
        let to_beat = best.map_or(f32::NEG_INFINITY, |(_, score)| score);
        if let Some(score) = vote.score(normal, to_beat) {
            best = Some((normal, score));
        }
    }
    let best = best.map(|(normal, _)| normal);
    let members = best.map(|best| agreeing(points, i, candidates, &vote, best)).unwrap_or_default();
    let normal = plane_normal(points, i, &members, scale);
    let refined = agreeing(points, i, candidates, &vote, normal);
    if refined.len() >= members.len() {
        let refitted = plane_normal(points, i, &refined, scale);
        (neighborhood(scan, i, refined, refitted), normal)
    } else {
        (neighborhood(scan, i, members, normal), best.unwrap_or(normal))
    }
}

/// The neighbourhood that `agreeing_neighborhood` found for point `i`, from the normal of the
/// plane that chose its members and the `normal` it fitted to them.
pub fn neighborhood_agreeing_with(
    points: &[Vec3],
    scan: &ScanLines,
    i: usize,
    candidates: &Candidates,
    (chooser, normal): (Vec3, Vec3),
) -> ScanNeighborhood {
    let scale = nearest_across(points, i, candidates);
    let members = agreeing(points, i, candidates, &plane_vote(points, scan, i, candidates, scale), chooser);
    neighborhood(scan, i, members, normal)
}

/// The vote over the window of point `i`.
fn plane_vote(points: &[Vec3], scan: &ScanLines, i: usize, candidates: &Candidates, scale: f32) -> PlaneVote {
    let ray = (points[i] - scan.sensor[i]).normalize_or_zero();
    let window = candidates.window.iter().map(|&j| points[j as usize] - points[i]);
    PlaneVote::new(window, scale, NOISE_SIGMAS * scan.range_noise, ray)
}

/// The window's returns that lie near the plane through point `i` of unit normal `normal`.
fn agreeing(points: &[Vec3], i: usize, candidates: &Candidates, vote: &PlaneVote, normal: Vec3) -> Vec<u32> {
    let offset = |j: u32| points[j as usize] - points[i];
    candidates.window.iter().copied().filter(|&j| vote.segment(offset(j), normal).agrees()).collect()
}

/// The neighbourhood of point `i` of `members` (in any order) and the `normal` of the plane
/// that fits them: the members sorted, and whether any lies on another line than the point.
fn neighborhood(scan: &ScanLines, i: usize, mut members: Vec<u32>, normal: Vec3) -> ScanNeighborhood {
    members.sort_unstable();
    let crosses_lines = members.iter().any(|&j| scan.line_of[j as usize] != scan.line_of[i]);
    ScanNeighborhood { members, normal, crosses_lines }
}

/// The unit normals of the planes through the origin, one of `along` and one of `across`,
/// that are not nearly in line with it; where fewer than two returns along the line seed them
/// (a pole, a narrow object, the end of a line), two of `across` or of `along`.
fn plane_hypotheses<'a>(along: &'a [Vec3], across: &'a [Vec3]) -> impl Iterator<Item = Vec3> + 'a {
    let crossing = along.iter().flat_map(move |&p| across.iter().map(move |&q| (p, q)));
    let pairs_of = |seeds: &'a [Vec3]| {
        seeds.iter().enumerate().flat_map(move |(a, &p)| seeds[a + 1..].iter().map(move |&q| (p, q)))
    };
    let few_along = along.len() < 2;
    let within = pairs_of(if across.is_empty() { along } else { across })
        .filter(move |_| few_along || across.is_empty());
    crossing.chain(within).filter_map(|(p, q)| {
        let normal = p.cross(q);
        (normal.length() > 0.1 * p.length() * q.length()).then(|| normal.normalize())
    })
}

/// The normal of the plane that fits point `i` and `members`: the least eigenvector of their
/// weighted scatter about their weighted mean. Each return weighs as its direction from the
/// point would, `1 / distance²`, so that the next line, metres away, does not outweigh the
/// returns along the line; but a return nearer than `scale` (the nearest return on another
/// line) weighs only its share of that, since the range noise moves a return a few centimetres
/// away at random. About the mean, not the point: the point's own noise must not tilt the
/// plane. +z when the members leave it undefined.
fn plane_normal(points: &[Vec3], i: usize, members: &[u32], scale: f32) -> Vec3 {
    let scale = f64::from(scale);
    let weighted: Vec<(DVec3, f64)> = members
        .iter()
        .filter_map(|&j| {
            let offset = (points[j as usize] - points[i]).as_dvec3();
            let length = offset.length();
            let weight = if scale > 0.0 { (length / scale).min(1.0) } else { 1.0 };
            (length > 0.0).then(|| (offset, weight / (length * length)))
        })
        .collect();
    let own_weight = weighted.iter().map(|&(_, w)| w).fold(0.0, f64::max);
    let total: f64 = own_weight + weighted.iter().map(|&(_, w)| w).sum::<f64>();
    let mean = weighted.iter().map(|&(d, w)| d * w).sum::<DVec3>() / total;
    let spread = |d: DVec3, w: f64| {
        let c = d - mean;
        DMat3::from_cols(c * c.x, c * c.y, c * c.z) * w
    };
    let scatter = weighted.iter().fold(spread(DVec3::ZERO, own_weight), |s, &(d, w)| s + spread(d, w));
    let normal = smallest_eigenvector(scatter);
    if normal.is_finite() && normal.length_squared() > 0.5 { normal.as_vec3() } else { Vec3::Z }
}
