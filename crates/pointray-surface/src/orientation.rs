//! Orienting PCA normals (METHOD.md §2.2). PCA gives each normal up to sign; these make
//! the signs agree across the surface, or point them toward a known scanner position.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::component_signs::{SignedForest, component_links};
use crate::neighbors::Neighbors;
use crate::orientation_tree::{ComponentSummary, orient_block};

/// Neighbours per point that the orientation graph uses (a prefix of each row): enough
/// to connect a surface sampled unevenly, while fewer edges keep the pass fast and
/// reach less often across thin parts to the opposite side.
const ORIENTATION_K: usize = 10;

/// Points per block oriented on its own. Fixed, not derived from the thread count, so that
/// the result is the same on every machine. On 10M dragon points, blocks of 16,384 agreed
/// with the sampled faces on 99.55% of the points where one tree over the whole cloud did on
/// 99.70%; blocks of 65,536 give 99.70% too, and a million points still make 16 tasks.
const BLOCK_POINTS: usize = 65_536;

/// Hoppe et al. 1992: propagates orientation along a minimum spanning tree of the
/// symmetrised neighbour graph weighted by `1 - |n_i . n_j|`, so that signs cross
/// between nearly parallel normals first and sharp creases last. Each connected
/// component is then flipped as a whole so that its highest point (largest z) has an
/// upward normal, which is outward for a closed surface.
///
/// In parallel: the points (in Morton order, so each block of consecutive points is a
/// compact piece of the surface) are oriented block by block (`orientation_tree.rs`), then
/// the blocks' pieces are flipped to agree with each other by the votes of the edges
/// between them (`component_signs.rs`).
pub fn orient_consistently(points: &[Vec3], normals: &mut [Vec3], neighbors: &Neighbors) {
    let count = points.len().min(normals.len()).min(neighbors.point_count());
    let used_k = neighbors.k.min(ORIENTATION_K);
    let normals = &mut normals[..count];
    let mut labels = vec![0u32; count];
    let blocks: Vec<Vec<ComponentSummary>> = normals
        .par_chunks_mut(BLOCK_POINTS)
        .zip(labels.par_chunks_mut(BLOCK_POINTS))
        .enumerate()
        .map(|(b, (normals, labels))| {
            let block = b * BLOCK_POINTS..b * BLOCK_POINTS + normals.len();
            orient_block(points, neighbors, used_k, block, normals, labels)
        })
        .collect();
    number_components_across_blocks(&mut labels, &blocks);
    let components: Vec<ComponentSummary> = blocks.into_iter().flatten().collect();
    let mut forest =
        SignedForest::join(components.len(), component_links(neighbors, used_k, normals, &labels));
    let flips = component_flips(&components, &mut forest, points, normals, &labels);
    normals.par_iter_mut().zip(&labels).for_each(|(normal, &c)| {
        if flips[c as usize] {
            *normal = -*normal;
        }
    });
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

/// Below this |n.z| the highest point's normal is too close to horizontal to say which
/// side is up; the direction away from the component's centroid decides instead.
const MIN_UPWARD_Z: f32 = 0.1;

/// Block components are numbered within their block; this numbers them across the cloud.
fn number_components_across_blocks(labels: &mut [u32], blocks: &[Vec<ComponentSummary>]) {
    let mut offsets = Vec::with_capacity(blocks.len());
    let mut total = 0u32;
    for block in blocks {
        offsets.push(total);
        total += block.len() as u32;
    }
    labels.par_chunks_mut(BLOCK_POINTS).zip(offsets).for_each(|(labels, offset)| {
        labels.iter_mut().for_each(|label| *label += offset);
    });
}

/// What decides which way a joined component faces: its highest point and its centroid.
#[derive(Clone, Copy)]
struct Outward {
    top: u32,
    position_sum: DVec3,
    count: u64,
}

/// Whether each block component must flip: to agree with its tree's root, and then so that
/// the whole tree's highest point's normal points up (or away from the tree's centroid
/// when that normal is near horizontal).
fn component_flips(
    components: &[ComponentSummary],
    forest: &mut SignedForest,
    points: &[Vec3],
    normals: &[Vec3],
    labels: &[u32],
) -> Vec<bool> {
    let to_root: Vec<(u32, bool)> = (0..components.len() as u32).map(|c| forest.find(c)).collect();
    let mut trees: Vec<Option<Outward>> = vec![None; components.len()];
    for (component, &(root, _)) in components.iter().zip(&to_root) {
        let tree = trees[root as usize].get_or_insert(Outward {
            top: component.top,
            position_sum: DVec3::ZERO,
            count: 0,
        });
        if points[component.top as usize].z > points[tree.top as usize].z {
            tree.top = component.top;
        }
        tree.position_sum += component.position_sum;
        tree.count += u64::from(component.count);
    }
    let points_inward = |tree: &Outward| {
        let top = tree.top as usize;
        let top_normal = if to_root[labels[top] as usize].1 { -normals[top] } else { normals[top] };
        let outward_score = if top_normal.z.abs() >= MIN_UPWARD_Z {
            top_normal.z
        } else {
            let centroid = (tree.position_sum / tree.count as f64).as_vec3();
            top_normal.dot(points[top] - centroid)
        };
        outward_score < 0.0
    };
    let tree_flips: Vec<bool> = trees.iter().map(|tree| tree.as_ref().is_some_and(points_inward)).collect();
    to_root.iter().map(|&(root, flip)| flip ^ tree_flips[root as usize]).collect()
}
