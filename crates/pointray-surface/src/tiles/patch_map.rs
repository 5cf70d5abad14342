//! Each input point's patch, noted tile by tile as a tiled prep's patches are put in order:
//! a tile's colour neighbours name input points, and the merged patches name patches.

use pointray_kernels::NO_NEIGHBOR;

pub(crate) struct PatchMap {
    /// Indexed by input point; `NO_NEIGHBOR` for points merged away.
    patch_of: Vec<u32>,
}

impl PatchMap {
    /// A map of `input_points` points, none with a patch yet.
    pub(crate) fn new(input_points: usize) -> Self {
        Self { patch_of: vec![NO_NEIGHBOR; input_points] }
    }

    /// Notes that the patches made from the input points `sources`, in order, are numbered
    /// from `first`.
    pub(crate) fn note(&mut self, sources: &[u32], first: u64) {
        for (patch, &input) in sources.iter().enumerate() {
            self.patch_of[input as usize] = (first + patch as u64) as u32;
        }
    }

    /// The patch of input point `input`: `NO_NEIGHBOR` for one merged away, and for
    /// `NO_NEIGHBOR` itself.
    pub(crate) fn patch(&self, input: u32) -> u32 {
        self.patch_of.get(input as usize).copied().unwrap_or(NO_NEIGHBOR)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patches_are_numbered_in_the_order_noted() {
        let mut map = PatchMap::new(5);
        map.note(&[3, 0], 0);
        map.note(&[4], 2);
        let patches: Vec<u32> = (0..5).map(|input| map.patch(input)).collect();
        assert_eq!(patches, [1, NO_NEIGHBOR, NO_NEIGHBOR, 0, 2]);
        assert_eq!(map.patch(NO_NEIGHBOR), NO_NEIGHBOR);
    }
}
