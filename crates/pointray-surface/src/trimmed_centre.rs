//! The point a cloud is recentred on before its coordinates drop to f32. The bounding box's
//! centre follows a single far point: a model beside one junk return 1e4 away would sit 5e3
//! out, where f32 steps are a thousand times coarser, and its close neighbours would merge
//! as duplicates. So each axis takes the middle of the range that holds all but the
//! outermost percent of the points, found on a fixed sample of them, so that every route
//! (whole, in tiles, streamed in chunks) finds the same centre.

use glam::DVec3;

/// At most about this many points, evenly spaced in input order, place the centre.
pub(crate) const CENTRE_SAMPLE_POINTS: u64 = 1 << 16;

/// The share of the sample left out at each end of each axis.
const TRIMMED_SHARE: f64 = 0.01;

/// The sample of a cloud of known size, gathered from its points in input order.
pub(crate) struct CentreSample {
    stride: u64,
    positions: Vec<DVec3>,
}

impl CentreSample {
    /// A sample of a cloud of `points` points.
    pub fn new(points: u64) -> Self {
        let stride = points.div_ceil(CENTRE_SAMPLE_POINTS).max(1);
        Self { stride, positions: Vec::with_capacity(points.div_ceil(stride) as usize) }
    }

    /// Takes the sampled points among `positions`, the cloud's points from index `first` on.
    pub fn offer(&mut self, first: u64, positions: &[DVec3]) {
        let start = (first.next_multiple_of(self.stride) - first) as usize;
        self.positions.extend(positions.iter().skip(start).step_by(self.stride as usize));
    }

    /// The centre of the trimmed ranges (the origin for an empty sample).
    pub fn centre(self) -> DVec3 {
        let axis = |pick: fn(DVec3) -> f64| trimmed_middle(self.positions.iter().map(|&p| pick(p)).collect());
        DVec3::new(axis(|p| p.x), axis(|p| p.y), axis(|p| p.z))
    }
}

/// The trimmed centre of a cloud held in memory: the offset `prep` recentres it on.
pub fn trimmed_centre(positions: &[DVec3]) -> DVec3 {
    let mut sample = CentreSample::new(positions.len() as u64);
    sample.offer(0, positions);
    sample.centre()
}

/// The middle of `values` with the outermost `TRIMMED_SHARE` left out at each end.
fn trimmed_middle(mut values: Vec<f64>) -> f64 {
    let Some(last) = values.len().checked_sub(1) else { return 0.0 };
    let trimmed = ((values.len() as f64 * TRIMMED_SHARE).ceil() as usize).min(last / 2);
    let low = *values.select_nth_unstable_by(trimmed, f64::total_cmp).1;
    let high = *values.select_nth_unstable_by(last - trimmed, f64::total_cmp).1;
    (low + high) * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(count: usize) -> Vec<DVec3> {
        (0..count).map(|i| DVec3::new(i as f64, 2.0 * i as f64, -(i as f64))).collect()
    }

    #[test]
    fn one_far_point_does_not_move_the_centre() {
        let mut positions = line(1001);
        positions.push(DVec3::splat(1e4));
        let centre = trimmed_centre(&positions);
        assert!((centre - DVec3::new(500.0, 1000.0, -500.0)).abs().max_element() < 20.0, "{centre}");
    }

    #[test]
    fn a_sample_offered_in_chunks_finds_the_centre_of_the_whole() {
        let positions = line(300_001);
        let mut chunked = CentreSample::new(positions.len() as u64);
        let mut first = 0;
        for chunk in positions.chunks(7_777) {
            chunked.offer(first, chunk);
            first += chunk.len() as u64;
        }
        assert_eq!(chunked.centre(), trimmed_centre(&positions));
        assert!((trimmed_centre(&positions) - DVec3::new(150_000.0, 300_000.0, -150_000.0)).length() < 10.0);
    }

    #[test]
    fn tiny_and_empty_clouds_have_centres() {
        assert_eq!(trimmed_centre(&[]), DVec3::ZERO);
        assert_eq!(trimmed_centre(&[DVec3::ONE]), DVec3::ONE);
        assert_eq!(trimmed_centre(&line(3)), DVec3::new(1.0, 2.0, -1.0));
    }
}
