//! The k nearest neighbours of many points at once, from a grid of cells about as wide as a
//! neighbourhood. kiddo's tree answers one query at a time (about 1.9 us on one core for 17
//! neighbours, mostly spent walking the tree); here each query scans the points of the
//! 3 x 3 x 3 cells around its own, a block that consecutive queries in one cell share. The
//! answer is exact when its farthest neighbour lies nearer than the block's faces, beyond
//! which every other point lies. Queries where it is not get a block of 5 x 5 x 5 cells; when
//! few are left after that, wider blocks still, since building the tree for them would cost
//! more than all the grid's queries. The rest (sparse points, crowded blocks) are left to the
//! tree.

use glam::{IVec3, UVec3, Vec3};
use rayon::prelude::*;

use crate::morton::finite_bounds;
use crate::neighbors::{neighbour_key, neighbour_of};

/// A block of 3 x 3 x 3 or 5 x 5 x 5 cells holding more candidates than this leaves its
/// queries to the wider blocks, if any, and the tree: scanning them would cost more than the
/// tree's walk.
const MOST_CANDIDATES: usize = 768;

/// The most candidates of the wider blocks, which only a few queries scan.
const MOST_FAR_CANDIDATES: usize = 8192;

/// The cells on each side of a query's own that the blocks take in, in turn: `NEAR_REACHES`
/// for every query, `FAR_REACHES` for the few that those leave.
const NEAR_REACHES: [i32; 2] = [1, 2];
const FAR_REACHES: [i32; 2] = [4, 8];

/// Points sampled, evenly along the input, to size the cells.
const SIZE_SAMPLES: usize = 4096;

/// The points on either side of a sampled point along the input among which its
/// neighbourhood is measured: inputs in Morton order (as prep's) keep a neighbourhood
/// nearby; others get wide cells, and the tree.
const SIZE_WINDOW: usize = 32;

/// Bits of each cell coordinate: cells are widened until the cloud spans at most this many
/// an axis.
const AXIS_BITS: u32 = 20;

/// An occupied cell's coordinates, packed so that one (x, y) column of cells is contiguous
/// and ordered by z.
type CellKey = u64;

pub(crate) struct CellGrid<'a> {
    points: &'a [Vec3],
    origin: Vec3,
    width: f32,
    /// Rounding of positions, as far as the block's faces are concerned.
    slack: f32,
    /// Point indices, grouped by cell in key order.
    members: Vec<u32>,
    /// The occupied cells' keys, ascending.
    keys: Vec<CellKey>,
    /// Where each occupied cell's members start in `members`, then their end.
    starts: Vec<u32>,
}

impl<'a> CellGrid<'a> {
    /// A grid over `points` sized for their `wanted` nearest points; none when the points
    /// give no finite size.
    pub(crate) fn new(points: &'a [Vec3], wanted: usize) -> Option<Self> {
        let (min, max) = finite_bounds(points)?;
        let extent = (max - min).max_element();
        let width = typical_radius(points, wanted)?.max(extent / (1 << AXIS_BITS) as f32);
        if !(width.is_finite() && width > 0.0) {
            return None;
        }
        let slack = 8.0 * f32::EPSILON * (min.abs().max(max.abs()).max_element() + extent);
        let mut grid = Self {
            points,
            origin: min,
            width,
            slack,
            members: Vec::new(),
            keys: Vec::new(),
            starts: Vec::new(),
        };
        let mut keyed: Vec<(CellKey, u32)> =
            points.par_iter().enumerate().map(|(i, &p)| (key(grid.cell_of(p)), i as u32)).collect();
        keyed.par_sort_unstable();
        let firsts: Vec<usize> =
            (0..keyed.len()).into_par_iter().filter(|&i| i == 0 || keyed[i].0 != keyed[i - 1].0).collect();
        grid.keys = firsts.par_iter().map(|&i| keyed[i].0).collect();
        grid.starts = firsts.iter().map(|&i| i as u32).chain([keyed.len() as u32]).collect();
        grid.members = keyed.into_par_iter().map(|(_, i)| i).collect();
        Some(grid)
    }

    /// The points `queries` (positions in the cloud), cell by cell: queries of one cell share
    /// its block, so each block is gathered about once.
    pub(crate) fn cell_by_cell(&self, queries: &[usize]) -> Vec<usize> {
        let mut order: Vec<(CellKey, usize)> =
            queries.iter().map(|&i| (key(self.cell_of(self.points[i])), i)).collect();
        order.sort_unstable();
        order.into_iter().map(|(_, i)| i).collect()
    }

    fn cell_of(&self, p: Vec3) -> UVec3 {
        let most = Vec3::splat(((1 << AXIS_BITS) - 1) as f32);
        ((p - self.origin) / self.width).floor().clamp(Vec3::ZERO, most).as_uvec3()
    }

    /// Gathers into `block` the points of the cells within its reach of `cell` (itself
    /// included).
    fn gather_block(&self, cell: UVec3, block: &mut Block) {
        block.clear(cell);
        let (cell, reach) = (cell.as_ivec3(), block.reach);
        let last = (1 << AXIS_BITS) - 1;
        for (dx, dy) in (-reach..=reach).flat_map(|dx| (-reach..=reach).map(move |dy| (dx, dy))) {
            let column = cell + IVec3::new(dx, dy, 0);
            if column.x < 0 || column.y < 0 || column.x > last || column.y > last {
                continue;
            }
            let low = key(column.with_z((cell.z - reach).max(0)).as_uvec3());
            let high = key(column.with_z((cell.z + reach).min(last)).as_uvec3());
            let first = self.keys.partition_point(|&k| k < low);
            let cells = self.keys[first..].iter().take_while(|&&k| k <= high).count();
            let members = self.starts[first] as usize..self.starts[first + cells] as usize;
            if block.len() + members.len() > block.most {
                block.crowded = true;
                return;
            }
            block.extend(self.points, &self.members[members]);
        }
    }

    /// The nearest `wanted` points to point `query` (itself among them) as `neighbour_key`s,
    /// nearest first, ties by index, in `nearest`; false when the grid cannot tell them for
    /// sure, and the tree must. `within`, when given, is a squared distance within which
    /// `wanted` points are known to lie: only the block's points within it are sorted.
    /// `blocks` keep the last queries' blocks.
    pub(crate) fn nearest(
        &self,
        query: (usize, usize),
        within: Option<f32>,
        blocks: &mut Blocks,
        nearest: &mut Vec<u64>,
    ) -> bool {
        for block in &mut blocks.0 {
            if self.nearest_in_block(query, within, block, nearest) {
                return true;
            }
            // A wider block would be more crowded still.
            if block.crowded {
                return false;
            }
        }
        false
    }

    /// As `nearest`, from `block` alone.
    fn nearest_in_block(
        &self,
        (query, wanted): (usize, usize),
        within: Option<f32>,
        block: &mut Block,
        nearest: &mut Vec<u64>,
    ) -> bool {
        let p = self.points[query];
        let cell = self.cell_of(p);
        if block.cell != Some(cell) {
            self.gather_block(cell, block);
        }
        nearest.clear();
        if block.crowded || block.len() < wanted {
            return false;
        }
        block.squared_distances(p);
        block.keys_within(within.unwrap_or(f32::INFINITY), nearest);
        if nearest.len() < wanted {
            block.keys_within(f32::INFINITY, nearest);
        }
        // Only points at no finite distance (not a number) are missing.
        if nearest.len() < wanted {
            return false;
        }
        if nearest.len() > wanted {
            nearest.select_nth_unstable(wanted - 1);
            nearest.truncate(wanted);
        }
        nearest.sort_unstable();
        let depth = self.depth_in_block(p, cell, block.reach);
        depth > 0.0 && neighbour_of(nearest[wanted - 1]).0 < depth * depth
    }

    /// How far `p` (in `cell`) lies inside the block of cells within `reach` of it: every
    /// point outside the block is farther.
    fn depth_in_block(&self, p: Vec3, cell: UVec3, reach: i32) -> f32 {
        let low = self.origin + (cell.as_vec3() - Vec3::splat(reach as f32)) * self.width;
        let high = self.origin + (cell.as_vec3() + Vec3::splat((reach + 1) as f32)) * self.width;
        (p - low).min(high - p).min_element() - self.slack
    }
}

fn key(cell: UVec3) -> CellKey {
    (u64::from(cell.x) << (2 * AXIS_BITS)) | (u64::from(cell.y) << AXIS_BITS) | u64::from(cell.z)
}

/// The median, over points sampled evenly along the input, of the distance to the
/// `wanted`-th nearest of the points around each along the input: an upper bound on its
/// neighbourhood's radius.
fn typical_radius(points: &[Vec3], wanted: usize) -> Option<f32> {
    if points.len() <= wanted || wanted == 0 {
        return None;
    }
    let step = (points.len() / SIZE_SAMPLES).max(1);
    let mut radii: Vec<f32> = (0..points.len())
        .into_par_iter()
        .step_by(step)
        .map_init(Vec::new, |squared: &mut Vec<f32>, i| {
            let window = i.saturating_sub(SIZE_WINDOW)..(i + SIZE_WINDOW + 1).min(points.len());
            squared.clear();
            squared.extend(window.filter(|&j| j != i).map(|j| points[j].distance_squared(points[i])));
            let nth = (wanted - 1).min(squared.len() - 1);
            *squared.select_nth_unstable_by(nth, f32::total_cmp).1
        })
        .collect();
    let middle = radii.len() / 2;
    Some(radii.select_nth_unstable_by(middle, f32::total_cmp).1.sqrt())
}

/// The blocks a query tries in turn, each kept for the next query.
pub(crate) struct Blocks(Vec<Block>);

impl Blocks {
    /// The blocks every query tries: its 3 x 3 x 3 cells, then its 5 x 5 x 5.
    pub(crate) fn near() -> Self {
        Self(NEAR_REACHES.iter().map(|&reach| Block::reaching(reach, MOST_CANDIDATES)).collect())
    }

    /// The wider blocks for the few queries that the near ones leave.
    pub(crate) fn far() -> Self {
        Self(FAR_REACHES.iter().map(|&reach| Block::reaching(reach, MOST_FAR_CANDIDATES)).collect())
    }
}

/// The points of one block, coordinate by coordinate so that distances to all of them are
/// computed side by side.
struct Block {
    cell: Option<UVec3>,
    /// The cells on each side of the block's own that it takes in.
    reach: i32,
    /// The most candidates it scans.
    most: usize,
    crowded: bool,
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    index: Vec<u32>,
    /// Squared distances to the current query, one per point.
    squared: Vec<f32>,
}

impl Block {
    /// An empty block of the cells within `reach` of its own (1: 3 x 3 x 3 cells), holding
    /// at most `most` points.
    fn reaching(reach: i32, most: usize) -> Self {
        Self {
            cell: None,
            reach,
            most,
            crowded: false,
            x: Vec::new(),
            y: Vec::new(),
            z: Vec::new(),
            index: Vec::new(),
            squared: Vec::new(),
        }
    }

    fn clear(&mut self, cell: UVec3) {
        self.cell = Some(cell);
        self.crowded = false;
        [&mut self.x, &mut self.y, &mut self.z].into_iter().for_each(Vec::clear);
        self.index.clear();
    }

    fn len(&self) -> usize {
        self.index.len()
    }

    /// Fills `squared` with each point's squared distance to `p`, side by side.
    fn squared_distances(&mut self, p: Vec3) {
        let count = self.index.len();
        self.squared.resize(count, 0.0);
        let (x, y, z) = (&self.x[..count], &self.y[..count], &self.z[..count]);
        for (i, squared) in self.squared.iter_mut().enumerate() {
            let (dx, dy, dz) = (x[i] - p.x, y[i] - p.y, z[i] - p.z);
            *squared = dx * dx + dy * dy + dz * dz;
        }
    }

    /// The `neighbour_key`s of the points within squared distance `within`, in `keys`;
    /// written whether kept or not, so that the loop does not branch on the distance.
    fn keys_within(&self, within: f32, keys: &mut Vec<u64>) {
        keys.resize(self.squared.len(), 0);
        let mut kept = 0;
        for (&squared, &index) in self.squared.iter().zip(&self.index) {
            keys[kept] = neighbour_key(squared, index);
            kept += usize::from(squared <= within);
        }
        keys.truncate(kept);
    }

    fn extend(&mut self, points: &[Vec3], members: &[u32]) {
        for &i in members {
            let p = points[i as usize];
            self.x.push(p.x);
            self.y.push(p.y);
            self.z.push(p.z);
        }
        self.index.extend_from_slice(members);
    }
}

#[cfg(test)]
mod tests {
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::morton::morton_order;
    use crate::neighbors::k_nearest;

    /// The `k` nearest of each point other than itself by brute force, ties by index.
    fn brute_force(points: &[Vec3], k: usize) -> Vec<Vec<u32>> {
        (0..points.len())
            .map(|i| {
                let mut keys: Vec<u64> = (0..points.len())
                    .filter(|&j| j != i)
                    .map(|j| {
                        let d = points[j] - points[i];
                        neighbour_key(d.x * d.x + d.y * d.y + d.z * d.z, j as u32)
                    })
                    .collect();
                keys.sort_unstable();
                keys[..k].iter().map(|&key| neighbour_of(key).1).collect()
            })
            .collect()
    }

    /// A wavy sheet sampled unevenly (a dense patch beside a sparse one), with coincident
    /// points, points on a regular lattice (equal distances) and far outliers, in Morton
    /// order as prep takes them.
    fn awkward_cloud(seed: u64) -> Vec<Vec3> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut points: Vec<Vec3> = (0..3000)
            .map(|i| {
                let spread = if i % 3 == 0 { 0.2 } else { 1.0 };
                let (x, y) = (rng.random::<f32>() * spread, rng.random::<f32>() * spread);
                Vec3::new(x, y, 0.05 * (7.0 * x).sin() * (5.0 * y).cos())
            })
            .collect();
        let copies: Vec<Vec3> = (0..100).map(|i| points[i * 7]).collect();
        points.extend(copies);
        points.extend((0..400).map(|i| Vec3::new(2.0 + (i % 20) as f32 * 0.01, (i / 20) as f32 * 0.01, 0.0)));
        points.extend([Vec3::new(40.0, 0.0, 0.0), Vec3::new(0.0, -30.0, 9.0), Vec3::new(5.0, 5.0, 5.0)]);
        let order = morton_order(&points);
        order.iter().map(|&i| points[i as usize]).collect()
    }

    #[test]
    fn the_table_holds_the_nearest_points_in_distance_then_index_order() {
        for seed in 0..3 {
            let points = awkward_cloud(seed);
            for k in [1, 8, 16] {
                let table = k_nearest(&points, k);
                let expected = brute_force(&points, k);
                for (i, row) in expected.iter().enumerate() {
                    assert_eq!(table.of(i), row.as_slice(), "seed {seed}, k {k}, point {i}");
                }
            }
        }
    }

    #[test]
    fn the_grid_settles_most_queries_of_an_even_surface_and_declines_the_rest() {
        let points = awkward_cloud(7);
        let grid = CellGrid::new(&points, 17).expect("a finite size");
        let (mut block, mut nearest) = (Block::reaching(1, MOST_CANDIDATES), Vec::new());
        let settled = (0..points.len())
            .filter(|&i| grid.nearest_in_block((i, 17), None, &mut block, &mut nearest))
            .count();
        assert!(settled * 10 > points.len() * 8, "{settled} of {} settled", points.len());
        let outlier = points.iter().position(|p| p.x == 40.0).expect("the outlier");
        assert!(
            !grid.nearest((outlier, 17), None, &mut Blocks::far(), &mut nearest),
            "an isolated point goes to the tree"
        );
    }

    #[test]
    fn wider_blocks_settle_all_but_the_far_outliers() {
        let points = awkward_cloud(7);
        let grid = CellGrid::new(&points, 17).expect("a finite size");
        let (mut narrow, mut nearest) = (Block::reaching(1, MOST_CANDIDATES), Vec::new());
        let left: Vec<usize> = (0..points.len())
            .filter(|&i| !grid.nearest_in_block((i, 17), None, &mut narrow, &mut nearest))
            .collect();
        let (mut near, mut far) = (Blocks::near(), Blocks::far());
        let unsettled: Vec<Vec3> = left
            .iter()
            .filter(|&&i| {
                !grid.nearest((i, 17), None, &mut near, &mut nearest)
                    && !grid.nearest((i, 17), None, &mut far, &mut nearest)
            })
            .map(|&i| points[i])
            .collect();
        assert!(left.len() > unsettled.len() + 10, "{} left by the narrow blocks", left.len());
        assert!(unsettled.iter().all(|p| p.length() > 4.0), "only the far outliers are left: {unsettled:?}");
    }
}
