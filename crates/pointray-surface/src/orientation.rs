//! Orienting PCA normals (SPEC.md §2.2). PCA gives each normal up to sign; these make
//! the signs agree across the surface, or point them toward a known scanner position.

use glam::Vec3;
use rayon::prelude::*;

use crate::neighbors::Neighbors;

/// Neighbours per point that the orientation graph uses (a prefix of each row): enough
/// to connect a surface sampled unevenly, while fewer edges keep the pass fast and
/// reach less often across thin parts to the opposite side.
const ORIENTATION_K: usize = 10;

/// Edge weights `1 - |n_i . n_j|` are bucketed on the square-root scale, which is about
/// linear in the angle between the normals: 1024 levels resolve well under a degree
/// near zero, where nearly all edges of a smooth surface lie.
const WEIGHT_LEVELS: usize = 1024;

/// Hoppe et al. 1992: propagates orientation along a minimum spanning tree of the
/// symmetrised neighbour graph weighted by `1 - |n_i . n_j|`, so that signs cross
/// between nearly parallel normals first and sharp creases last. Each connected
/// component is then flipped as a whole so that its highest point (largest z) has an
/// upward normal, which is outward for a closed surface.
///
/// The tree is grown by Prim's algorithm with a bucket queue over quantised weights:
/// O(1) per edge, and the quantisation changes only the order among near-equal weights.
pub fn orient_consistently(points: &[Vec3], normals: &mut [Vec3], neighbors: &Neighbors) {
    let count = points.len().min(normals.len()).min(neighbors.point_count());
    let graph = SymmetricGraph::new(neighbors, count, neighbors.k.min(ORIENTATION_K));
    let mut visited = vec![false; count];
    let mut queue = BucketQueue::new(WEIGHT_LEVELS);
    let mut component = Vec::new();
    for start in 0..count {
        if !visited[start] {
            component.clear();
            let mut tree = TreeGrowth { graph: &graph, normals, visited: &mut visited, queue: &mut queue };
            tree.grow_from(start, &mut component);
            flip_outward(points, normals, &component);
        }
    }
}

/// Flips each normal that faces away from `sensor`, the position the points were seen
/// from: a visible surface faces its scanner.
pub fn orient_toward(points: &[Vec3], normals: &mut [Vec3], sensor: Vec3) {
    normals.par_iter_mut().zip(points.par_iter()).for_each(|(normal, &p)| {
        if normal.dot(sensor - p) < 0.0 {
            *normal = -*normal;
        }
    });
}

/// The kNN graph with every edge usable both ways: a point need not be among its own
/// neighbours' neighbours, and Prim must still reach it.
struct SymmetricGraph<'a> {
    neighbors: &'a Neighbors,
    used_k: usize,
    /// Edges `j -> i` for each `i -> j` whose reverse is not already a kNN edge, grouped
    /// by `j`: `reverse[reverse_starts[j]..reverse_starts[j + 1]]`.
    reverse_starts: Vec<u32>,
    reverse: Vec<u32>,
}

impl<'a> SymmetricGraph<'a> {
    fn new(neighbors: &'a Neighbors, count: usize, used_k: usize) -> Self {
        let forward = |i: usize| &neighbors.of(i)[..used_k];
        let mut one_way: Vec<(u32, u32)> = (0..count)
            .into_par_iter()
            .flat_map_iter(|i| {
                forward(i).iter().filter_map(move |&j| {
                    let is_mutual = (j as usize) < count && forward(j as usize).contains(&(i as u32));
                    ((j as usize) < count && !is_mutual).then_some((j, i as u32))
                })
            })
            .collect();
        one_way.par_sort_unstable();
        let mut reverse_starts = vec![0u32; count + 1];
        for &(j, _) in &one_way {
            reverse_starts[j as usize + 1] += 1;
        }
        for i in 0..count {
            reverse_starts[i + 1] += reverse_starts[i];
        }
        let reverse = one_way.into_iter().map(|(_, i)| i).collect();
        Self { neighbors, used_k, reverse_starts, reverse }
    }

    fn adjacent(&self, v: usize) -> impl Iterator<Item = u32> + '_ {
        let reverse = &self.reverse[self.reverse_starts[v] as usize..self.reverse_starts[v + 1] as usize];
        self.neighbors.of(v)[..self.used_k].iter().chain(reverse).copied()
    }
}

/// The state of one Prim traversal.
struct TreeGrowth<'g, 'n> {
    graph: &'g SymmetricGraph<'g>,
    normals: &'n mut [Vec3],
    visited: &'n mut [bool],
    queue: &'n mut BucketQueue,
}

impl TreeGrowth<'_, '_> {
    /// Visits `start`'s whole component in minimum-spanning-tree order, making each new
    /// normal agree with the normal of the tree vertex it is reached from.
    fn grow_from(&mut self, start: usize, component: &mut Vec<u32>) {
        self.visit(start, component);
        while let Some((from, to)) = self.queue.pop() {
            let to = to as usize;
            if self.visited[to] {
                continue;
            }
            if self.normals[from as usize].dot(self.normals[to]) < 0.0 {
                self.normals[to] = -self.normals[to];
            }
            self.visit(to, component);
        }
    }

    fn visit(&mut self, v: usize, component: &mut Vec<u32>) {
        self.visited[v] = true;
        component.push(v as u32);
        let normal = self.normals[v];
        for w in self.graph.adjacent(v) {
            if !self.visited[w as usize] {
                self.queue.push(weight_level(normal, self.normals[w as usize]), v as u32, w);
            }
        }
    }
}

/// The bucket of the edge weight `1 - |a . b|` (unit normals).
fn weight_level(a: Vec3, b: Vec3) -> usize {
    let weight = (1.0 - a.dot(b).abs()).max(0.0);
    (weight.sqrt() * (WEIGHT_LEVELS - 1) as f32) as usize // saturating cast; NaN gives 0
}

/// A min-priority queue of edges over small integer levels. Prim pushes keys below the
/// current minimum too, so `lowest` moves both ways; within a level the order is LIFO.
struct BucketQueue {
    buckets: Vec<Vec<(u32, u32)>>,
    lowest: usize,
    len: usize,
}

impl BucketQueue {
    fn new(levels: usize) -> Self {
        Self { buckets: vec![Vec::new(); levels], lowest: levels, len: 0 }
    }

    fn push(&mut self, level: usize, from: u32, to: u32) {
        let level = level.min(self.buckets.len() - 1);
        self.buckets[level].push((from, to));
        self.lowest = self.lowest.min(level);
        self.len += 1;
    }

    fn pop(&mut self) -> Option<(u32, u32)> {
        if self.len == 0 {
            return None;
        }
        while self.buckets[self.lowest].is_empty() {
            self.lowest += 1;
        }
        self.len -= 1;
        self.buckets[self.lowest].pop()
    }
}

/// Below this |n.z| the highest point's normal is too close to horizontal to say which
/// side is up; the direction away from the component's centroid decides instead.
const MIN_UPWARD_Z: f32 = 0.1;

/// Flips the whole component when its highest point's normal points inward.
fn flip_outward(points: &[Vec3], normals: &mut [Vec3], component: &[u32]) {
    let Some(&top) =
        component.iter().max_by(|&&a, &&b| points[a as usize].z.total_cmp(&points[b as usize].z))
    else {
        return;
    };
    let (top_point, top_normal) = (points[top as usize], normals[top as usize]);
    let outward_score = if top_normal.z.abs() >= MIN_UPWARD_Z {
        top_normal.z
    } else {
        let centroid = component.iter().map(|&i| points[i as usize]).sum::<Vec3>() / component.len() as f32;
        top_normal.dot(top_point - centroid)
    };
    if outward_score < 0.0 {
        for &i in component {
            normals[i as usize] = -normals[i as usize];
        }
    }
}
