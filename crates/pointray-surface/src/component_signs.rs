//! Settling the signs between the blocks' components: each was oriented in itself, and the
//! neighbour edges between two of them vote on whether one must flip to agree with the
//! other. The strongest votes are taken first (Kruskal's algorithm on a union-find that
//! keeps each member's sign relative to its root), so a thin part's few edges across to
//! the opposite side lose to the many edges along the surface.

use glam::Vec3;
use rayon::prelude::*;

use crate::neighbors::Neighbors;

/// The summed agreement `n_i . n_j` over the edges between components `a < b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Link {
    pub(crate) a: u32,
    pub(crate) b: u32,
    pub(crate) agreement: f32,
}

/// The links between different components over the first `used_k` neighbours of each of
/// the first `labels.len()` points; `labels` numbers each point's component.
pub(crate) fn component_links(
    neighbors: &Neighbors,
    used_k: usize,
    normals: &[Vec3],
    labels: &[u32],
) -> Vec<Link> {
    let count = labels.len();
    let mut votes: Vec<(u32, u32, f32)> = (0..count)
        .into_par_iter()
        .with_min_len(4096)
        .flat_map_iter(|i| {
            let a = labels[i];
            let crossing = neighbors.of(i)[..used_k].iter().map(|&j| j as usize).filter(move |&j| j < count);
            crossing.filter(move |&j| labels[j] != a).map(move |j| {
                let b = labels[j];
                let agreement = normals[i].dot(normals[j]);
                (a.min(b), a.max(b), if agreement.is_finite() { agreement } else { 0.0 })
            })
        })
        .collect();
    // Ordering the votes fully makes each sum, and so the result, independent of threads.
    votes.par_sort_unstable_by_key(|&(a, b, agreement)| (a, b, agreement.to_bits()));
    let mut links: Vec<Link> = Vec::new();
    for (a, b, agreement) in votes {
        match links.last_mut() {
            Some(last) if (last.a, last.b) == (a, b) => last.agreement += agreement,
            _ => links.push(Link { a, b, agreement }),
        }
    }
    links
}

/// Components joined into trees, each member knowing whether it must flip to agree with
/// its tree's root.
pub(crate) struct SignedForest {
    parent: Vec<u32>,
    /// Whether a component's sign is opposite to its parent's.
    opposite_to_parent: Vec<bool>,
}

impl SignedForest {
    /// Joins `component_count` components along `links`, strongest first; a link that would
    /// close a cycle is outvoted by the stronger ones already taken.
    pub(crate) fn join(component_count: usize, mut links: Vec<Link>) -> Self {
        links.par_sort_unstable_by(|x, y| {
            y.agreement.abs().total_cmp(&x.agreement.abs()).then((x.a, x.b).cmp(&(y.a, y.b)))
        });
        let mut forest = Self {
            parent: (0..component_count as u32).collect(),
            opposite_to_parent: vec![false; component_count],
        };
        for link in links {
            let (root_a, flip_a) = forest.find(link.a);
            let (root_b, flip_b) = forest.find(link.b);
            if root_a != root_b {
                forest.parent[root_b as usize] = root_a;
                forest.opposite_to_parent[root_b as usize] = flip_a ^ flip_b ^ (link.agreement < 0.0);
            }
        }
        forest
    }

    /// The root of `component`'s tree, and whether `component` must flip to agree with it.
    /// Points every component on the way straight at the root.
    pub(crate) fn find(&mut self, component: u32) -> (u32, bool) {
        let (mut root, mut flip) = (component, false);
        while self.parent[root as usize] != root {
            flip ^= self.opposite_to_parent[root as usize];
            root = self.parent[root as usize];
        }
        let (mut c, mut c_flip) = (component, flip);
        while c != root {
            let (next, next_flip) = (self.parent[c as usize], c_flip ^ self.opposite_to_parent[c as usize]);
            self.parent[c as usize] = root;
            self.opposite_to_parent[c as usize] = c_flip;
            (c, c_flip) = (next, next_flip);
        }
        (root, flip)
    }
}
