//! Silhouettes in a LiDAR scan: where the next return along a line, or on the next line, lies
//! on another surface well in front of or behind a point, or the next line saw nothing there.
//! A patch in front (an occluder's edge) must stop short of the next ray, or it floats in front
//! of what that ray saw; a patch behind
//! (the surface an occluder hides) may reach under the occluder, where no one sees it, and so
//! close the corners between its lines at the silhouette.

use glam::Vec3;

use crate::scan::lines::{ScanLine, ScanLines};

/// A neighbour on another surface lies across a silhouette when its range differs from the
/// point's by more than this fraction of the point's range: a car's edge against the wall
/// behind it, not the foot of a wall or a kerb.
const DEPTH_JUMP_FRACTION: f32 = 0.05;

/// A line beside a return with no return within this many azimuth steps of it saw nothing
/// there; one step would take a single dropout for the sky.
const EMPTY_LINE_STEPS: f32 = 3.0;

/// Which side of a silhouette a point lies on, along one axis of its patch.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Silhouette {
    /// No silhouette next to it on this axis.
    #[default]
    None,
    /// The next return on this axis lies behind it, on a surface it occludes.
    InFront,
    /// The next return on this axis lies in front of it, on a surface that occludes it.
    Behind,
}

impl Silhouette {
    /// The two sides' verdicts as one: in front wins, so that no patch floats.
    fn and(self, other: Self) -> Self {
        match (self, other) {
            (Self::InFront, _) | (_, Self::InFront) => Self::InFront,
            (Self::Behind, _) | (_, Self::Behind) => Self::Behind,
            _ => Self::None,
        }
    }
}

/// The silhouettes beside point `i` along its line and across the lines, given the returns
/// (`members`, sorted) that agree with its surface.
pub fn silhouettes(points: &[Vec3], scan: &ScanLines, i: usize, members: &[u32]) -> (Silhouette, Silhouette) {
    let line = &scan.lines[scan.line_of[i] as usize];
    let position = line.members.partition_point(|&m| scan.azimuth[m as usize] < scan.azimuth[i]);
    let position =
        (position..line.members.len()).find(|&at| line.members[at] as usize == i).unwrap_or(position);
    let along = [position.checked_sub(1), Some(position + 1)]
        .into_iter()
        .flatten()
        .filter_map(|at| line.members.get(at).copied());
    let across = across_neighbours(scan, i);
    let side = |j: u32| silhouette(points, scan, i, j, members);
    let open = if sees_nothing_beside(scan, i) { Silhouette::InFront } else { Silhouette::None };
    (along.map(side).fold(Silhouette::None, Silhouette::and), across.map(side).fold(open, Silhouette::and))
}

/// The returns of the lines next below and above point `i`'s nearest its azimuth, when
/// within a step of it.
pub fn across_neighbours(scan: &ScanLines, i: usize) -> impl Iterator<Item = u32> + '_ {
    let line = &scan.lines[scan.line_of[i] as usize];
    let step = scan.azimuth_step(i).unwrap_or(0.0);
    [line.below, line.above]
        .into_iter()
        .flatten()
        .filter_map(move |l| nearest_in_azimuth(&scan.lines[l as usize], scan, scan.azimuth[i], step))
}

/// Whether a line next below or above point `i` has no return within `EMPTY_LINE_STEPS` of its
/// azimuth: that line's rays there met nothing (the sky over a roof, or past the sensor's
/// range), so the point's patch stops short of them as at an occluder's edge.
fn sees_nothing_beside(scan: &ScanLines, i: usize) -> bool {
    let line = &scan.lines[scan.line_of[i] as usize];
    let reach = EMPTY_LINE_STEPS * scan.azimuth_step(i).unwrap_or(0.0);
    [line.below, line.above]
        .into_iter()
        .flatten()
        .any(|l| nearest_in_azimuth(&scan.lines[l as usize], scan, scan.azimuth[i], reach).is_none())
}

/// The return of `line` nearest `azimuth`, when one lies within `step` of it.
fn nearest_in_azimuth(line: &ScanLine, scan: &ScanLines, azimuth: f32, step: f32) -> Option<u32> {
    let at = line.members.partition_point(|&m| scan.azimuth[m as usize] < azimuth);
    [at.checked_sub(1), Some(at)]
        .into_iter()
        .flatten()
        .filter_map(|k| line.members.get(k).copied())
        .map(|j| (j, (scan.azimuth[j as usize] - azimuth).abs()))
        .filter(|&(_, gap)| gap <= step)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(j, _)| j)
}

fn silhouette(points: &[Vec3], scan: &ScanLines, i: usize, j: u32, members: &[u32]) -> Silhouette {
    if members.binary_search(&j).is_ok() {
        return Silhouette::None;
    }
    let range = points[i].distance(scan.sensor[i]);
    let other = points[j as usize].distance(scan.sensor[j as usize]);
    let jump = DEPTH_JUMP_FRACTION * range;
    if other > range + jump {
        Silhouette::InFront
    } else if other < range - jump {
        Silhouette::Behind
    } else {
        Silhouette::None
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    /// Three lines 2° apart over a wall 10 m away, 0.2° azimuth steps from 0° to 12°; the top
    /// line returns only up to 6° (the wall's top edge, sky beyond) and drops the return at 3°.
    fn wall_scan() -> (Vec<Vec3>, ScanLines) {
        let mut points = Vec::new();
        let mut rings = Vec::new();
        for ring in 0..3u16 {
            let elevation = (f32::from(ring) * 2.0 - 2.0).to_radians();
            for step in 0..=60 {
                let azimuth = (step as f32 * 0.2).to_radians();
                if ring == 2 && (step > 30 || step == 15) {
                    continue;
                }
                let direction = Vec3::new(
                    azimuth.cos() * elevation.cos(),
                    azimuth.sin() * elevation.cos(),
                    elevation.sin(),
                );
                points.push(direction * (10.0 / direction.x));
                rings.push(ring);
            }
        }
        let sensors = vec![DVec3::ZERO; points.len()];
        let scan = ScanLines::new(&points, &sensors, Some(&rings)).expect("a scan");
        (points, scan)
    }

    #[test]
    fn a_line_that_saw_nothing_beside_a_return_is_an_edge_but_one_dropout_is_not() {
        let (points, scan) = wall_scan();
        let middle_at = |step: usize| 61 + step;
        let members: Vec<u32> = (0..points.len() as u32).collect();
        let across = |step: usize| silhouettes(&points, &scan, middle_at(step), &members).1;
        assert_eq!(across(10), Silhouette::None, "the top line returned beside it");
        assert_eq!(across(15), Silhouette::None, "one dropout on the top line is not the sky");
        assert_eq!(across(45), Silhouette::InFront, "the top line saw the sky there");
    }
}
