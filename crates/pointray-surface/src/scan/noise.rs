//! A scan's range noise, measured on its own lines: along a line the range changes smoothly
//! (a road seen by one beam is a circle of constant range, a wall a gentle curve), so the
//! second difference of three consecutive ranges is mostly noise. Its median, robust to the
//! range jumps at edges, gives the noise's standard deviation.

use glam::Vec3;

use crate::scan::lines::ScanLine;

/// Consecutive returns further apart in azimuth than this many of the line's steps have a
/// dropout or a gap between them, where the range need not change smoothly.
const MAX_GAP_STEPS: f32 = 1.5;

/// The standard deviation of a normal variable over the median of its absolute value.
const SIGMA_PER_MEDIAN_DEVIATION: f32 = 1.4826;

/// `r1 - (r0 + r2) / 2` has 1.5 times the variance of one range.
const SECOND_DIFFERENCE_SPREAD: f32 = 1.224_744_9;

/// The standard deviation of the range noise, in scene units, from the second differences of
/// ranges along `lines` (`offsets`: each point from its station; `azimuth`: around it); 0
/// when no line has three consecutive returns.
pub fn range_noise(lines: &[ScanLine], offsets: &[Vec3], azimuth: &[f32]) -> f32 {
    let mut deviations: Vec<f32> = lines
        .iter()
        .flat_map(|line| {
            let limit = MAX_GAP_STEPS * line.azimuth_step;
            line.members.windows(3).filter_map(move |triple| {
                let [a, b, c] = [triple[0], triple[1], triple[2]].map(|m| m as usize);
                let close = azimuth[b] - azimuth[a] <= limit && azimuth[c] - azimuth[b] <= limit;
                let range = |m: usize| offsets[m].length();
                close.then(|| (range(b) - 0.5 * (range(a) + range(c))).abs())
            })
        })
        .collect();
    if deviations.is_empty() {
        return 0.0;
    }
    let middle = deviations.len() / 2;
    let median = *deviations.select_nth_unstable_by(middle, f32::total_cmp).1;
    median * SIGMA_PER_MEDIAN_DEVIATION / SECOND_DIFFERENCE_SPREAD
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn the_noise_of_a_ring_on_a_wall_is_recovered() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let sigma = 0.02f32;
        let count = 4000;
        let step = 0.002f32;
        let (offsets, azimuth): (Vec<Vec3>, Vec<f32>) = (0..count)
            .map(|k| {
                let a = -4.0 + k as f32 * step;
                // A wall at x = 10 seen over ±4 rad would be too wide: use a circle of range 10
                // with a gentle bump, plus Gaussian noise from the Box-Muller transform.
                let (u, v): (f32, f32) = (rng.random_range(1e-6..1.0), rng.random_range(0.0..1.0));
                let noise = sigma * (-2.0 * u.ln()).sqrt() * (std::f32::consts::TAU * v).cos();
                let range = 10.0 + 0.5 * (a * 0.5).sin() + noise;
                (Vec3::new(a.cos(), a.sin(), 0.0) * range, a)
            })
            .unzip();
        let line = ScanLine {
            station: 0,
            elevation: 0.0,
            members: (0..count as u32).collect(),
            azimuth_step: step,
            below: None,
            above: None,
        };
        let estimate = range_noise(&[line], &offsets, &azimuth);
        assert!((estimate - sigma).abs() < 0.15 * sigma, "{estimate}");
    }
}
