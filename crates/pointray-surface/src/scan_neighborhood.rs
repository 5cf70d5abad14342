//! A point's neighbourhood in a LiDAR scan: the returns beside it on its own scan line and
//! the nearest by azimuth on the lines above and below, so that no support comes from its own
//! line alone; then only those that agree with one surface through the point.

use glam::{DMat3, Vec3};

use crate::normals::smallest_eigenvector;
use crate::scan_lines::{ScanLine, ScanLines};

/// Returns taken on each side of the point along its own line, this many steps away: along a
/// line returns lie closer together than the range noise, so the far ones give the line's
/// direction and the near ones the patch's reach.
const ALONG_LINE_STEPS: [usize; 4] = [1, 2, 4, 8];

/// A neighbour belongs to the point's surface when the segment to it rises at most this
/// steeply out of the point's tangent plane (about 6°): gently curved bodies stay in, the foot
/// of a wall and the range jump from a car's edge to the wall behind it do not. Looser, a plane
/// tilted halfway between the ground and a wall would take in the returns of both.
const MAX_RISE: f32 = 0.1;

/// Range noise, as a fraction of the range: a neighbour may lie this much further out of the
/// plane than `MAX_RISE` allows. Automotive sensors measure to 2 to 3 cm, so on a wall 7 m away
/// two returns 4 cm apart can differ by as much out of the plane as along it.
const RANGE_NOISE_FRACTION: f32 = 0.005;

/// A point's neighbourhood: the indices that agree on one surface, and its unit normal
/// (not oriented). `crosses_lines` tells whether any of them lies on another line.
#[derive(Clone, Debug, PartialEq)]
pub struct ScanNeighborhood {
    pub members: Vec<u32>,
    pub normal: Vec3,
    pub crosses_lines: bool,
}

/// Returns on other lines count only this many azimuth steps of the point's own line away:
/// where a line has no return near the point's azimuth (out of range, or a dropout), its
/// nearest return in azimuth lies elsewhere in the scene.
const AZIMUTH_STEPS: f32 = 3.0;

/// The candidates of point `i`: `ALONG_LINE_STEPS` on each side along its line, and on each
/// nearby line the two returns whose azimuths bracket its own.
pub fn candidates(scan: &ScanLines, i: usize) -> Vec<u32> {
    let line = &scan.lines[scan.line_of[i] as usize];
    let position = line.members.partition_point(|&m| scan.azimuth[m as usize] < scan.azimuth[i]);
    let position =
        (position..line.members.len()).find(|&at| line.members[at] as usize == i).unwrap_or(position);
    let found: Vec<u32> = ALONG_LINE_STEPS
        .iter()
        .flat_map(|&step| [position.checked_sub(step), Some(position + step)])
        .flatten()
        .filter_map(|at| line.members.get(at).copied())
        .collect();
    let azimuth = scan.azimuth[i];
    let beside = [position.checked_sub(1), Some(position + 1)].into_iter().flatten();
    let step = beside
        .filter_map(|at| line.members.get(at))
        .map(|&j| (scan.azimuth[j as usize] - azimuth).abs())
        .fold(0.0f32, f32::max);
    let reach = AZIMUTH_STEPS * step.max(1e-4);
    let across = scan
        .nearby_lines(i)
        .flat_map(|other| bracketing(other, scan, azimuth))
        .filter(|&j| (scan.azimuth[j as usize] - azimuth).abs() <= reach);
    found.iter().copied().chain(across).collect()
}

/// The members of `line` just before and after `azimuth`.
fn bracketing<'a>(line: &'a ScanLine, scan: &ScanLines, azimuth: f32) -> impl Iterator<Item = u32> + 'a {
    let at = line.members.partition_point(|&m| scan.azimuth[m as usize] < azimuth);
    [at.checked_sub(1), Some(at)].into_iter().flatten().filter_map(|k| line.members.get(k).copied())
}

/// The neighbourhood of point `i` among `candidates`: of the planes through the point and two
/// candidates, the one that most candidates lie near (a small exhaustive RANSAC: a wall's
/// returns must not tilt the ground at its foot), refined by PCA over those that agree.
pub fn agreeing_neighborhood(
    points: &[Vec3],
    scan: &ScanLines,
    i: usize,
    candidates: &[u32],
) -> ScanNeighborhood {
    let offsets: Vec<Vec3> = candidates.iter().map(|&j| points[j as usize] - points[i]).collect();
    let line = scan.line_of[i];
    let scale = candidates
        .iter()
        .zip(&offsets)
        .filter(|&(&j, _)| scan.line_of[j as usize] != line)
        .map(|(_, d)| d.length())
        .fold(f32::INFINITY, f32::min);
    let scale = if scale.is_finite() { scale } else { 0.0 };
    let noise = RANGE_NOISE_FRACTION * points[i].distance(scan.sensor[i]);
    let slope = |offset: Vec3, normal: Vec3| slope(offset, normal, scale, noise);
    let agreeing = |normal: Vec3| -> Vec<u32> {
        candidates
            .iter()
            .zip(&offsets)
            .filter(|&(_, &d)| slope(d, normal) <= MAX_RISE)
            .map(|(&j, _)| j)
            .collect()
    };
    // Most agreeing candidates first, then the flattest fit among them.
    let score = |normal: Vec3| {
        let slopes = offsets.iter().map(|&d| slope(d, normal)).filter(|&s| s <= MAX_RISE);
        slopes.fold(0.0f32, |score, s| score + 1.0 - s)
    };
    let best = plane_hypotheses(&offsets).max_by(|&a, &b| score(a).total_cmp(&score(b)));
    let mut members = best.map(agreeing).unwrap_or_default();
    let mut normal = plane_normal(points, i, &members, scale);
    let refined = agreeing(normal);
    if refined.len() >= members.len() {
        normal = plane_normal(points, i, &refined, scale);
        members = refined;
    }
    let crosses_lines = members.iter().any(|&j| scan.line_of[j as usize] != line);
    ScanNeighborhood { members, normal, crosses_lines }
}

/// The unit normals of the planes through the origin and two of `offsets` that are not
/// nearly in line with it.
fn plane_hypotheses(offsets: &[Vec3]) -> impl Iterator<Item = Vec3> + '_ {
    (0..offsets.len()).flat_map(move |a| {
        (a + 1..offsets.len()).filter_map(move |b| {
            let (p, q) = (offsets[a], offsets[b]);
            let normal = p.cross(q);
            (normal.length() > 0.1 * p.length() * q.length()).then(|| normal.normalize())
        })
    })
}

/// How steeply the segment `offset` rises out of the plane of `normal`, less `noise`. Short
/// segments count as if half the neighbourhood's `scale` long: along a line, returns can lie
/// closer together than the range noise.
fn slope(offset: Vec3, normal: Vec3, scale: f32, noise: f32) -> f32 {
    let rise = (offset.dot(normal).abs() - noise).max(0.0);
    let run = (offset - offset.dot(normal) * normal).length();
    rise / run.max(0.5 * scale).max(f32::MIN_POSITIVE)
}

/// The normal of the plane through point `i` that the directions to `members` lie closest
/// to: the least eigenvector of their scatter. Directions rather than offsets, so that the
/// next line, metres away, does not outweigh the returns along the line (with offsets, one
/// return a little off the plane out there would tilt it); but a direction to a return
/// nearer than `scale` (the nearest return on another line) weighs only its share of it,
/// since the range noise turns the direction to a return a few centimetres away at random.
/// +z when the members leave it undefined.
fn plane_normal(points: &[Vec3], i: usize, members: &[u32], scale: f32) -> Vec3 {
    let scale = f64::from(scale);
    let scatter = members
        .iter()
        .filter_map(|&j| {
            let offset = (points[j as usize] - points[i]).as_dvec3();
            let length = offset.length();
            let weight = if scale > 0.0 { (length / scale).min(1.0) } else { 1.0 };
            (length > 0.0).then(|| offset / length * weight.sqrt())
        })
        .fold(DMat3::ZERO, |scatter, u| scatter + DMat3::from_cols(u * u.x, u * u.y, u * u.z));
    let normal = smallest_eigenvector(scatter);
    if normal.is_finite() && normal.length_squared() > 0.5 { normal.as_vec3() } else { Vec3::Z }
}
