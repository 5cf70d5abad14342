//! Morton (Z-order) sorting: every later stage (kNN, fit, BVH build) gains from the
//! locality, and some acceleration-structure builders need sorted primitives.

use glam::Vec3;
use rayon::prelude::*;

/// Bits per axis: 3 x 21 = 63 bits fit one `u64` code.
const BITS_PER_AXIS: u32 = 21;
const MAX_CELL: f32 = ((1u32 << BITS_PER_AXIS) - 1) as f32;

/// The permutation that sorts `points` along a Morton curve over their bounding box:
/// `sorted[i] = points[perm[i]]`. Ties (points in one cell) keep input order, so the
/// result is deterministic. Non-finite coordinates land in cell 0 of their axis.
pub fn morton_order(points: &[Vec3]) -> Vec<u32> {
    curve_and_order(points).1
}

/// The grid of the curve `morton_order` sorts `points` along (none when no point is finite),
/// and that order.
pub(crate) fn curve_and_order(points: &[Vec3]) -> (Option<MortonGrid>, Vec<u32>) {
    let Some(grid) = MortonGrid::of(points) else {
        return (None, (0..points.len() as u32).collect());
    };
    let mut keyed: Vec<(u64, u32)> =
        points.par_iter().enumerate().map(|(i, &p)| (grid.code(p), i as u32)).collect();
    keyed.par_sort_unstable();
    (Some(grid), keyed.into_iter().map(|(_, i)| i).collect())
}

/// The cells of a Morton curve over a bounding box: sorting by (code, input index) is the
/// order `morton_order` gives, so points sorted out of core land where it puts them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MortonGrid {
    min: Vec3,
    scale: Vec3,
}

impl MortonGrid {
    /// The grid `morton_order` sorts `points` along: over their finite bounding box; none
    /// when no point is finite.
    fn of(points: &[Vec3]) -> Option<Self> {
        finite_bounds(points).map(|(min, max)| Self::over(min, max))
    }

    /// The grid over the box from `min` to `max`.
    pub fn over(min: Vec3, max: Vec3) -> Self {
        // One scale for all axes (the bounding cube): per-axis scales would stretch a flat
        // axis to full resolution and make the curve zigzag across it.
        let extent = (max - min).max_element().max(f32::MIN_POSITIVE);
        Self { min, scale: Vec3::splat(MAX_CELL / extent) }
    }

    /// The grid's corner and its cells' scale, as a kept sort's index stores them.
    pub(crate) fn parts(&self) -> (Vec3, f32) {
        (self.min, self.scale.x)
    }

    /// The grid of `parts`.
    pub(crate) fn from_parts(min: Vec3, scale: f32) -> Self {
        Self { min, scale: Vec3::splat(scale) }
    }

    /// The interleaved 63-bit code of `p`'s cell.
    pub fn code(&self, p: Vec3) -> u64 {
        morton_code(p, self.min, self.scale)
    }
}

/// The bounding box of the finite points, or `None` when there are none.
pub(crate) fn finite_bounds(points: &[Vec3]) -> Option<(Vec3, Vec3)> {
    points
        .par_iter()
        .filter(|p| p.is_finite())
        .map(|&p| (p, p))
        .reduce_with(|a, b| (a.0.min(b.0), a.1.max(b.1)))
}

/// The interleaved 63-bit code of `p`'s cell. Float-to-int casts saturate (NaN gives 0).
fn morton_code(p: Vec3, min: Vec3, scale: Vec3) -> u64 {
    let cell = ((p - min) * scale).clamp(Vec3::ZERO, Vec3::splat(MAX_CELL));
    spread_bits(cell.x as u32) | (spread_bits(cell.y as u32) << 1) | (spread_bits(cell.z as u32) << 2)
}

/// Puts two zero bits between each of the low 21 bits of `v`.
fn spread_bits(v: u32) -> u64 {
    let mut x = u64::from(v) & 0x1f_ffff;
    x = (x | (x << 32)) & 0x001f_0000_0000_ffff;
    x = (x | (x << 16)) & 0x001f_0000_ff00_00ff;
    x = (x | (x << 8)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x << 4)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_bits_interleaves() {
        assert_eq!(spread_bits(0b1), 0b1);
        assert_eq!(spread_bits(0b11), 0b1001);
        assert_eq!(spread_bits(0x1f_ffff), 0x1249_2492_4924_9249);
    }
}
