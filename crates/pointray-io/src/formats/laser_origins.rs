//! Where a spinning sensor's lasers fire from. Multi-block heads such as the Velodyne HDL-64E
//! mount their lasers in blocks at different heights, and write returns from each laser's own
//! origin. Seen from the sensor's origin, a laser's elevation then drifts by degrees with range;
//! seen from its block's origin, it holds to thousandths of a degree.
//!
//! A laser `h` above the origin at elevation `e` puts a return at horizontal distance `ρ` at
//! `z / ρ = tan e + h / ρ`, so a straight-line fit of `z / ρ` against `1 / ρ` over each line's
//! returns gives its height. Lasers whose heights lie within `BLOCK_GAP` form one block, which
//! fires from its lasers' median height.

use glam::DVec3;

/// Returns nearer than this (metres, horizontally) are left out of the fit: a few are noisy
/// enough at close range to tilt it.
const MIN_FIT_DISTANCE: f64 = 2.0;

/// A line's fit needs this many returns.
const MIN_FIT_RETURNS: usize = 50;

/// Lasers whose heights differ by less than this (metres) share a block.
const BLOCK_GAP: f64 = 0.02;

/// Heights nearer the origin than this (metres) leave the returns' sensor where it is.
const NEGLIGIBLE_HEIGHT: f64 = 0.005;

/// Per return, the origin of its laser's block, when the lasers fire from somewhere other than
/// the sensor's origin; `None` when they do not, or when too few lines can be fitted.
pub fn block_origins(positions: &[DVec3], rings: &[u16]) -> Option<Vec<DVec3>> {
    let heights = line_heights(positions, rings);
    let fitted: Vec<f64> = heights.iter().flatten().copied().collect();
    if fitted.len() * 2 < heights.len() {
        return None;
    }
    let blocks = blocks(fitted);
    let height_of_line: Vec<f64> = heights
        .iter()
        .map(|height| nearest_block(&blocks, height.unwrap_or_else(|| blocks[blocks.len() / 2])))
        .collect();
    if height_of_line.iter().all(|h| h.abs() < NEGLIGIBLE_HEIGHT) {
        return None;
    }
    Some(rings.iter().map(|&ring| DVec3::new(0.0, 0.0, height_of_line[usize::from(ring)])).collect())
}

/// Each line's laser height from the fit, `None` for lines with too few distant returns.
fn line_heights(positions: &[DVec3], rings: &[u16]) -> Vec<Option<f64>> {
    let lines = rings.iter().map(|&ring| usize::from(ring) + 1).max().unwrap_or(0);
    let mut sums = vec![LineFit::default(); lines];
    for (position, &ring) in positions.iter().zip(rings) {
        let horizontal = position.x.hypot(position.y);
        if horizontal >= MIN_FIT_DISTANCE && position.is_finite() {
            sums[usize::from(ring)].add(1.0 / horizontal, position.z / horizontal);
        }
    }
    sums.iter().map(LineFit::slope).collect()
}

/// The sums of a straight-line least-squares fit.
#[derive(Clone, Copy, Debug, Default)]
struct LineFit {
    count: usize,
    x: f64,
    y: f64,
    xx: f64,
    xy: f64,
}

impl LineFit {
    fn add(&mut self, x: f64, y: f64) {
        self.count += 1;
        self.x += x;
        self.y += y;
        self.xx += x * x;
        self.xy += x * y;
    }

    fn slope(&self) -> Option<f64> {
        let n = self.count as f64;
        let spread = n * self.xx - self.x * self.x;
        (self.count >= MIN_FIT_RETURNS && spread > f64::EPSILON * n * self.xx)
            .then(|| (n * self.xy - self.x * self.y) / spread)
    }
}

/// The median height of each group of heights that lie within `BLOCK_GAP` of the next.
fn blocks(mut heights: Vec<f64>) -> Vec<f64> {
    heights.sort_by(f64::total_cmp);
    let mut blocks = Vec::new();
    let mut start = 0;
    for end in 1..=heights.len() {
        if end == heights.len() || heights[end] - heights[end - 1] > BLOCK_GAP {
            blocks.push(heights[(start + end) / 2]);
            start = end;
        }
    }
    blocks
}

fn nearest_block(blocks: &[f64], height: f64) -> f64 {
    blocks.iter().copied().min_by(|a, b| (a - height).abs().total_cmp(&(b - height).abs())).unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two blocks of four lasers, 0.2 m and 0.12 m above the origin, over a varied scene.
    fn two_blocks() -> (Vec<DVec3>, Vec<u16>) {
        let mut positions = Vec::new();
        let mut rings = Vec::new();
        for laser in 0..8u16 {
            let (height, elevation) =
                if laser < 4 { (0.2, 2.0 - f64::from(laser)) } else { (0.12, -8.0 - f64::from(laser)) };
            for column in 0..400 {
                let azimuth = f64::from(column) * 0.9f64.to_radians();
                let range = 3.0 + 40.0 * (f64::from(column) * 0.37).sin().abs();
                let (e, a) = (elevation.to_radians(), azimuth);
                positions.push(
                    DVec3::new(0.0, 0.0, height)
                        + DVec3::new(a.cos() * e.cos(), a.sin() * e.cos(), e.sin()) * range,
                );
                rings.push(laser);
            }
        }
        (positions, rings)
    }

    #[test]
    fn each_block_fires_from_its_own_height() {
        let (positions, rings) = two_blocks();
        let origins = block_origins(&positions, &rings).expect("two blocks");
        assert!((origins[0].z - 0.2).abs() < 1e-3, "{}", origins[0].z);
        assert!((origins[positions.len() - 1].z - 0.12).abs() < 1e-3);
    }

    #[test]
    fn lasers_at_the_origin_leave_the_sensor_there() {
        let (positions, rings) = two_blocks();
        let at_origin: Vec<DVec3> = positions
            .iter()
            .zip(&rings)
            .map(|(&p, &ring)| p - DVec3::new(0.0, 0.0, if ring < 4 { 0.2 } else { 0.12 }))
            .collect();
        assert!(block_origins(&at_origin, &rings).is_none());
    }
}
