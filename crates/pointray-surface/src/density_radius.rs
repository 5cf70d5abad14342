//! Support radii that adapt to the local density.
//!
//! The paper's `d_i` (METHOD.md §2.3) reaches the farthest of the `k` nearest neighbours.
//! On real scans that fails two ways. Where the neighbours all lie on one side of `p_i` or
//! along one scan line, the disk does not reach across the gap beside it, and the surface
//! tears. Where a point is isolated, its neighbours are far and its box is huge.
//!
//! The adaptive radius keeps the paper's radius and corrects it twice:
//! 1. **Coverage.** The disks cover the surface when every point of each point's Voronoi
//!    cell (the part of its tangent plane closer to it than to any neighbour) lies in some
//!    disk. Where part of `p_i`'s cell lies in neither its own disk nor a neighbour's,
//!    `d_i` grows to reach the farthest such part. On evenly sampled surfaces the paper's
//!    disks overlap so much that this seldom happens; it is the gaps beside one-sided
//!    neighbourhoods and between scan lines that it fills.
//!    A cell left open on one side (a true border, a scan line whose neighbour lines are
//!    out of reach) is cut at the farthest neighbour the table holds.
//! 2. **Band.** `d_i` is then held within a factor `BAND` of the median paper radius of
//!    `p_i` and its `k` neighbours, so that an isolated point does not grow far beyond
//!    what the neighbourhood's spacing supports.
//!
//! The cell radius goes the other way: `d_i` is just what covers the point's own Voronoi
//! cell (its farthest corner, with a margin), whatever the paper's radius. The cells tile
//! the surface, so the disks still cover it, but each surface point lies under a patch or
//! two instead of about `k`: rays test fewer patches, and fewer wrong ones.

use glam::Vec2;
use rayon::prelude::*;

use crate::neighbors::Neighbors;
use pointray_kernels::TangentFrame;

/// The cell radius is this multiple of the cell's farthest corner: neighbouring patches lie
/// in slightly different tangent planes, and a ray meets a curved patch away from where its
/// hit projects into the tangent plane, so each disk must reach past its cell. On random
/// samples of three meshes a margin of 1.15 left 10–18 hole pixels where the paper's radius
/// left 0–2, 1.3 left 3–9 and 1.5 left 1–7, still with less false surface than the paper's.
pub const CELL_MARGIN: f32 = 1.5;

/// `d_i` lies within `[median / BAND, median * BAND]` of the neighbourhood's paper radii.
/// Measured on scan-line samples of the bunny and horse (bench/FIDELITY.md): a band of 1.5
/// kept a third to a half of the paper's holes; 3 without the cut of open cells at the
/// farthest neighbour closed them all but tripled the false surface; 3 with the cut gave
/// the best balance of those tried.
pub const BAND: f32 = 3.0;

/// How many adaptive radii differ from the paper's, and why.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RadiusAdjustments {
    /// Grown to cover the part of the Voronoi cell that no other disk covers.
    pub widened: usize,
    /// Held down to the top of the band.
    pub capped: usize,
    /// Raised to the bottom of the band.
    pub raised: usize,
}

/// The adaptive radii from the paper's `paper` radii. The first `k` entries of each
/// neighbour row are the fit's neighbours (the band); all of the row's entries shape the
/// Voronoi cell and may cover it.
pub fn adaptive_radii(
    frames: &[TangentFrame],
    points: &[glam::Vec3],
    neighbors: &Neighbors,
    k: usize,
    paper: &[f32],
) -> (Vec<f32>, RadiusAdjustments) {
    let outcomes: Vec<(f32, Option<Adjustment>)> = (0..points.len())
        .into_par_iter()
        .map_init(Surroundings::default, |around, i| {
            around.gather(i, frames, points, neighbors, k, paper);
            adjust(paper[i], uncovered_reach(&around.cell, paper[i], &around.disks), around.median)
        })
        .collect();
    let count = |wanted| outcomes.par_iter().filter(|(_, adjustment)| *adjustment == Some(wanted)).count();
    let adjustments = RadiusAdjustments {
        widened: count(Adjustment::Widened),
        capped: count(Adjustment::Capped),
        raised: count(Adjustment::Raised),
    };
    (outcomes.into_iter().map(|(radius, _)| radius).collect(), adjustments)
}

/// The cell radii (`RadiusMode::Cell`): `CELL_MARGIN` times each point's farthest Voronoi
/// corner, the cell cut as for the adaptive radius, held to at most the paper's radius (an
/// open cell, at a border or between scan lines, would otherwise grow false surface).
pub fn cell_radii(
    frames: &[TangentFrame],
    points: &[glam::Vec3],
    neighbors: &Neighbors,
    k: usize,
    paper: &[f32],
) -> Vec<f32> {
    (0..points.len())
        .into_par_iter()
        .map_init(Surroundings::default, |around, i| {
            around.gather(i, frames, points, neighbors, k, paper);
            let reach = CELL_MARGIN * around.cell.iter().map(|corner| corner.length()).fold(0.0, f32::max);
            reach.min(paper[i])
        })
        .collect()
}

/// A point's neighbours in its tangent plane (with their paper radii), its Voronoi cell
/// among them, and the band's median. Gathered for one point after another into the same
/// buffers, so that no point allocates.
#[derive(Default)]
struct Surroundings {
    disks: Vec<(Vec2, f32)>,
    cell: Vec<Vec2>,
    median: f32,
    band: Vec<f32>,
    clipped: Vec<Vec2>,
}

impl Surroundings {
    fn gather(
        &mut self,
        i: usize,
        frames: &[TangentFrame],
        points: &[glam::Vec3],
        neighbors: &Neighbors,
        k: usize,
        paper: &[f32],
    ) {
        self.median = band_median(paper, i, &neighbors.of(i)[..k], &mut self.band);
        self.disks.clear();
        self.disks.extend(neighbors.of(i).iter().map(|&j| {
            let local = frames[i].to_local(points[j as usize] - points[i]);
            (Vec2::new(local.x, local.y), paper[j as usize])
        }));
        // Past the farthest neighbour the table knows nothing of the surface, so an open
        // cell is cut there (and at the band's top).
        let known = neighbors.distances_of(i).last().copied().unwrap_or(0.0);
        let limit = known.min(BAND * self.median);
        let centres = self.disks.iter().map(|&(centre, _)| centre);
        voronoi_cell(centres, limit, &mut self.cell, &mut self.clipped);
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Adjustment {
    Widened,
    Capped,
    Raised,
}

/// The paper's radius, widened to `covering`, then held in the band around `median`.
fn adjust(paper: f32, covering: f32, median: f32) -> (f32, Option<Adjustment>) {
    let (low, high) = (median / BAND, median * BAND);
    let wanted = paper.max(covering);
    if wanted > high {
        (high, Some(Adjustment::Capped))
    } else if wanted < low {
        (low, Some(Adjustment::Raised))
    } else if wanted > paper {
        (wanted, Some(Adjustment::Widened))
    } else {
        (paper, None)
    }
}

/// The median of the paper radii of point `i` and its fit neighbours, gathered in `radii`.
fn band_median(paper: &[f32], i: usize, fit_neighbors: &[u32], radii: &mut Vec<f32>) -> f32 {
    radii.clear();
    radii.extend(std::iter::once(paper[i]).chain(fit_neighbors.iter().map(|&j| paper[j as usize])));
    let middle = radii.len() / 2;
    *radii.select_nth_unstable_by(middle, f32::total_cmp).1
}

/// How far from the origin the cell `cell` reaches outside the origin's own disk of
/// `radius` and every disk of `disks` (centre, radius), judged at its corners and the
/// middles of its edges; 0 when all of those are covered.
pub fn uncovered_reach(cell: &[Vec2], radius: f32, disks: &[(Vec2, f32)]) -> f32 {
    let edge_middles = cell.iter().zip(cell.iter().cycle().skip(1)).map(|(&a, &b)| 0.5 * (a + b));
    cell.iter()
        .copied()
        .chain(edge_middles)
        .filter(|probe| probe.length() > radius)
        .filter(|probe| !disks.iter().any(|&(centre, r)| centre.distance(*probe) <= r))
        .map(Vec2::length)
        .fold(0.0, f32::max)
}

/// Into `cell`, the origin's Voronoi cell among the `neighbors` (tangent-plane offsets) as a
/// convex polygon, cut to the square of half-size `limit`: a cell left open on one side
/// reaches `limit` there. `clipped` is a second buffer, used in turn with `cell`.
pub fn voronoi_cell(
    neighbors: impl Iterator<Item = Vec2>,
    limit: f32,
    cell: &mut Vec<Vec2>,
    clipped: &mut Vec<Vec2>,
) {
    cell.clear();
    cell.extend([
        Vec2::new(-limit, -limit),
        Vec2::new(limit, -limit),
        Vec2::new(limit, limit),
        Vec2::new(-limit, limit),
    ]);
    for q in neighbors {
        let half_distance_squared = 0.5 * q.length_squared();
        // A coincident neighbour cuts nothing: the origin would lie on its bisector. Nor
        // does one whose bisector passes beyond every corner.
        if half_distance_squared > 0.0 && cell.iter().any(|corner| corner.dot(q) > half_distance_squared) {
            clip_to_half_plane(cell, q, half_distance_squared, clipped);
            std::mem::swap(cell, clipped);
        }
    }
}

/// Sutherland-Hodgman: into `clipped`, the part of convex polygon `polygon` where
/// `x·q <= bound`, the side of the bisector between the origin and `q` that holds the origin.
fn clip_to_half_plane(polygon: &[Vec2], q: Vec2, bound: f32, clipped: &mut Vec<Vec2>) {
    clipped.clear();
    for (index, &current) in polygon.iter().enumerate() {
        let next = polygon[(index + 1) % polygon.len()];
        let (current_side, next_side) = (current.dot(q) - bound, next.dot(q) - bound);
        if current_side <= 0.0 {
            clipped.push(current);
        }
        if (current_side < 0.0 && next_side > 0.0) || (current_side > 0.0 && next_side < 0.0) {
            let t = current_side / (current_side - next_side);
            clipped.push(current + t * (next - current));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell_of(neighbors: impl Iterator<Item = Vec2>, limit: f32) -> Vec<Vec2> {
        let mut cell = Vec::new();
        voronoi_cell(neighbors, limit, &mut cell, &mut Vec::new());
        cell
    }

    fn farthest_corner(cell: &[Vec2]) -> f32 {
        cell.iter().map(|corner| corner.length()).fold(0.0, f32::max)
    }

    const GRID: [Vec2; 8] = [
        Vec2::X,
        Vec2::NEG_X,
        Vec2::Y,
        Vec2::NEG_Y,
        Vec2::ONE,
        Vec2::NEG_ONE,
        Vec2::new(1.0, -1.0),
        Vec2::new(-1.0, 1.0),
    ];

    #[test]
    fn a_square_grid_cell_is_the_unit_square() {
        let reach = farthest_corner(&cell_of(GRID.into_iter(), 100.0));
        assert!((reach - 0.5f32.hypot(0.5)).abs() < 1e-6, "{reach}");
    }

    #[test]
    fn a_cell_open_on_one_side_reaches_the_limit() {
        let one_side = [Vec2::X, Vec2::new(1.0, 1.0), Vec2::new(1.0, -1.0)];
        let reach = farthest_corner(&cell_of(one_side.into_iter(), 10.0));
        assert!((reach - 10.0 * 2f32.sqrt()).abs() < 1e-4, "{reach}");
    }

    #[test]
    fn coincident_neighbours_cut_nothing() {
        assert_eq!(farthest_corner(&cell_of([Vec2::ZERO].into_iter(), 1.0)), 2f32.sqrt());
    }

    #[test]
    fn a_cell_covered_by_the_neighbours_disks_needs_no_reach() {
        let cell = cell_of(GRID.into_iter(), 100.0);
        let wide: Vec<(Vec2, f32)> = GRID.iter().map(|&centre| (centre, 1.5)).collect();
        assert_eq!(uncovered_reach(&cell, 0.1, &wide), 0.0);
        let tiny: Vec<(Vec2, f32)> = GRID.iter().map(|&centre| (centre, 0.1)).collect();
        assert!((uncovered_reach(&cell, 0.1, &tiny) - 0.5f32.hypot(0.5)).abs() < 1e-6);
        assert_eq!(uncovered_reach(&cell, 1.0, &tiny), 0.0, "its own disk covers it");
    }

    #[test]
    fn adjustments_keep_the_band() {
        assert_eq!(adjust(1.0, 0.5, 1.0), (1.0, None));
        assert_eq!(adjust(1.0, 1.5, 1.0), (1.5, Some(Adjustment::Widened)));
        assert_eq!(adjust(1.0, 9.0, 1.0), (BAND, Some(Adjustment::Capped)));
        assert_eq!(adjust(9.0, 0.0, 1.0), (BAND, Some(Adjustment::Capped)));
        assert_eq!(adjust(0.1, 0.0, 1.0), (1.0 / BAND, Some(Adjustment::Raised)));
    }

    #[test]
    fn the_cell_radius_reaches_the_cells_corner_and_never_past_the_papers() {
        let points: Vec<glam::Vec3> =
            (0..9).map(|i| glam::Vec3::new((i % 3) as f32, (i / 3) as f32, 0.0)).collect();
        let frames = vec![TangentFrame::from_normal_and_angle(glam::Vec3::Z, 0.0); points.len()];
        let neighbors = crate::neighbors::k_nearest(&points, 8);
        let paper = vec![2.0; points.len()];
        let radii = cell_radii(&frames, &points, &neighbors, 8, &paper);
        let centre = 4;
        assert!((radii[centre] - CELL_MARGIN * 0.5f32.hypot(0.5)).abs() < 1e-5, "{}", radii[centre]);
        assert!(radii.iter().all(|&r| r <= 2.0), "{radii:?}");
        let tight = cell_radii(&frames, &points, &neighbors, 8, &vec![0.3; points.len()]);
        assert!(tight.iter().all(|&r| r == 0.3), "{tight:?}");
    }

    #[test]
    fn the_band_median_includes_the_point() {
        let paper = [5.0, 1.0, 2.0, 3.0];
        assert_eq!(band_median(&paper, 0, &[1, 2, 3], &mut Vec::new()), 3.0);
    }
}
