//! A tile's stretch of the Morton curve, by the codes of its first and last points. A code
//! never falls as any coordinate grows, so every point of a box lies, by code, between its
//! corners' codes: a box whose corners' codes lie strictly inside the stretch holds no point
//! of another tile.

use glam::Vec3;

use crate::morton::MortonGrid;

pub(crate) struct CurveSpan {
    grid: MortonGrid,
    first: u64,
    last: u64,
}

impl CurveSpan {
    /// The stretch of `grid`'s curve from code `first` to code `last`, both held by the tile
    /// (points of equal codes may fall on either side of a tile's ends).
    pub(crate) fn new(grid: MortonGrid, first: u64, last: u64) -> Self {
        Self { grid, first, last }
    }

    /// Whether the box from `lo` to `hi` holds no point outside the stretch.
    pub(crate) fn holds(&self, (lo, hi): (Vec3, Vec3)) -> bool {
        lo.is_finite() && hi.is_finite() && self.grid.code(lo) > self.first && self.grid.code(hi) < self.last
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_inside_the_stretch_holds_only_its_points() {
        let grid = MortonGrid::over(Vec3::ZERO, Vec3::ONE);
        let points: Vec<Vec3> = (0..4096)
            .map(|i| Vec3::new((i % 16) as f32, (i / 16 % 16) as f32, (i / 256) as f32) / 15.0)
            .collect();
        let mut codes: Vec<u64> = points.iter().map(|&p| grid.code(p)).collect();
        codes.sort_unstable();
        let (first, last) = (codes[1000], codes[3000]);
        let span = CurveSpan::new(grid, first, last);
        let boxes = (0..2000).map(|i| {
            let corner = points[(i * 7919) % points.len()];
            (corner, corner + Vec3::new(0.05, 0.1, 0.2) * (i % 5) as f32)
        });
        let mut held = 0;
        for (lo, hi) in boxes {
            if !span.holds((lo, hi)) {
                continue;
            }
            held += 1;
            let inside = points.iter().filter(|p| p.cmpge(lo).all() && p.cmple(hi).all());
            for p in inside {
                let code = grid.code(*p);
                assert!(code > first && code < last, "{p} in a held box lies outside the stretch");
            }
        }
        assert!(held > 100, "some boxes are held: {held}");
        assert!(!span.holds((Vec3::ZERO, Vec3::ONE)), "the whole cloud is not");
        assert!(!span.holds((Vec3::NAN, Vec3::ONE)));
    }
}
