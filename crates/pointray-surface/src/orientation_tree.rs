//! Orientation inside one block of consecutive points (Morton order makes them a compact
//! piece of the surface): Hoppe et al.'s minimum spanning tree over the block's part of
//! the neighbour graph. Blocks are independent, so they are oriented in parallel; the
//! signs between them are settled afterwards (`component_signs.rs`).

use std::ops::Range;

use glam::{DVec3, Vec3};

use crate::neighbors::Neighbors;

/// Edge weights `1 - |n_i . n_j|` are bucketed on the square-root scale, which is about
/// linear in the angle between the normals: 1024 levels resolve well under a degree
/// near zero, where nearly all edges of a smooth surface lie.
const WEIGHT_LEVELS: usize = 1024;

/// One connected piece of a block, oriented consistently in itself: what the outward flip
/// of the whole component it belongs to needs.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ComponentSummary {
    /// The highest point (largest z), as an index into the cloud.
    pub(crate) top: u32,
    pub(crate) position_sum: DVec3,
    pub(crate) count: u32,
}

/// Orients `normals` (the block `block` of the cloud's normals) along minimum spanning
/// trees of the block's graph, grown by Prim's algorithm with a bucket queue over
/// quantised weights (O(1) per edge; quantising changes only the order among near-equal
/// weights), so that signs cross between nearly parallel normals first and sharp creases
/// last. Writes each point's component number (from 0, within the block) to `labels` and
/// returns one summary per component.
pub(crate) fn orient_block(
    points: &[Vec3],
    neighbors: &Neighbors,
    used_k: usize,
    block: Range<usize>,
    normals: &mut [Vec3],
    labels: &mut [u32],
) -> Vec<ComponentSummary> {
    let graph = BlockGraph::new(neighbors, used_k, block.clone());
    let mut visited = vec![false; block.len()];
    let mut queue = BucketQueue::new(WEIGHT_LEVELS);
    let mut component = Vec::new();
    let mut summaries = Vec::new();
    for start in 0..block.len() {
        if visited[start] {
            continue;
        }
        component.clear();
        let mut tree = TreeGrowth { graph: &graph, normals, visited: &mut visited, queue: &mut queue };
        tree.grow_from(start, &mut component);
        for &v in &component {
            labels[v as usize] = summaries.len() as u32;
        }
        summaries.push(summarise(points, block.start, &component));
    }
    summaries
}

fn summarise(points: &[Vec3], first: usize, component: &[u32]) -> ComponentSummary {
    let global = |v: u32| first + v as usize;
    let top = component.iter().map(|&v| global(v)).max_by(|&a, &b| points[a].z.total_cmp(&points[b].z));
    ComponentSummary {
        top: top.unwrap_or(first) as u32,
        position_sum: component.iter().map(|&v| points[global(v)].as_dvec3()).sum(),
        count: component.len() as u32,
    }
}

/// The block's part of the kNN graph (edges with both ends in the block), every edge usable
/// both ways: a point need not be among its own neighbours' neighbours, and Prim must
/// still reach it. Vertices are numbered from the block's first point.
struct BlockGraph<'a> {
    neighbors: &'a Neighbors,
    used_k: usize,
    block: Range<usize>,
    /// Edges `j -> i` for each `i -> j` whose reverse is not already a kNN edge, grouped
    /// by `j`: `reverse[reverse_starts[j]..reverse_starts[j + 1]]`.
    reverse_starts: Vec<u32>,
    reverse: Vec<u32>,
}

impl<'a> BlockGraph<'a> {
    fn new(neighbors: &'a Neighbors, used_k: usize, block: Range<usize>) -> Self {
        let mut graph = Self { neighbors, used_k, block, reverse_starts: Vec::new(), reverse: Vec::new() };
        let mut one_way: Vec<(u32, u32)> = (0..graph.block.len())
            .flat_map(|i| {
                let graph = &graph;
                graph
                    .forward(i)
                    .filter(move |&j| !graph.forward(j).any(|back| back == i))
                    .map(move |j| (j, i))
            })
            .map(|(j, i)| (j as u32, i as u32))
            .collect();
        one_way.sort_unstable();
        let mut starts = vec![0u32; graph.block.len() + 1];
        for &(j, _) in &one_way {
            starts[j as usize + 1] += 1;
        }
        for i in 0..graph.block.len() {
            starts[i + 1] += starts[i];
        }
        graph.reverse_starts = starts;
        graph.reverse = one_way.into_iter().map(|(_, i)| i).collect();
        graph
    }

    /// Vertex `v`'s own neighbours that lie in the block.
    fn forward(&self, v: usize) -> impl Iterator<Item = usize> + '_ {
        let row = &self.neighbors.of(self.block.start + v)[..self.used_k];
        row.iter().filter(|&&j| self.block.contains(&(j as usize))).map(|&j| j as usize - self.block.start)
    }

    fn adjacent(&self, v: usize) -> impl Iterator<Item = usize> + '_ {
        let reverse = &self.reverse[self.reverse_starts[v] as usize..self.reverse_starts[v + 1] as usize];
        self.forward(v).chain(reverse.iter().map(|&i| i as usize))
    }
}

/// The state of one Prim traversal.
struct TreeGrowth<'g, 'n> {
    graph: &'g BlockGraph<'g>,
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
            if !self.visited[w] {
                self.queue.push(weight_level(normal, self.normals[w]), v as u32, w as u32);
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
