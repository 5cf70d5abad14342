//! A per-pixel stream of uniform random numbers that is the same on every backend for a
//! seed. Twin of `shaders/random_sequence.glsl`.
//!
//! Each number is a hash of (seed, pixel, sample, dimension) in 32-bit integer arithmetic,
//! which GPUs and CPUs compute bit for bit alike, turned into a float by an exact scaling.
//! A path draws its numbers in a fixed order, so the CPU and the GPU follow the same path.

use glam::{UVec2, Vec2};

/// The PCG-RXS-M-XS output permutation of one LCG step (Jarzynski and Olano, "Hash Functions
/// for GPU Rendering", 2020): well mixed and cheap.
pub fn pcg_hash(value: u32) -> u32 {
    let state = value.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// The numbers of one sample of one pixel: `key` names the sample, `dimension` counts the
/// numbers drawn so far.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RandomSequence {
    pub key: u32,
    pub dimension: u32,
}

/// The sequence of sample `sample` of `pixel` under `seed`.
pub fn random_sequence(seed: u32, pixel: UVec2, sample: u32) -> RandomSequence {
    let key = pcg_hash(
        seed.wrapping_add(pcg_hash(pixel.x.wrapping_add(pcg_hash(pixel.y.wrapping_add(pcg_hash(sample)))))),
    );
    RandomSequence { key, dimension: 0 }
}

/// The next number, uniform in `[0, 1)`: the hash's top 24 bits, exactly representable.
/// The key and dimension go through two rounds: with one, the draws of different dimensions
/// of one sample are correlated enough to bias rare joint events (a glass slab's double
/// inner reflection came out 3 standard errors low over 2.4 million samples; two rounds
/// agree with an ideal generator).
pub fn random_next(sequence: &mut RandomSequence) -> f32 {
    let bits = pcg_hash(pcg_hash(sequence.key ^ pcg_hash(sequence.dimension)));
    sequence.dimension = sequence.dimension.wrapping_add(1);
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// The next two numbers, in order.
pub fn random_next2(sequence: &mut RandomSequence) -> Vec2 {
    let x = random_next(sequence);
    let y = random_next(sequence);
    Vec2::new(x, y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_seed_pixel_and_sample_give_the_same_numbers_every_time() {
        let mut a = random_sequence(7, UVec2::new(3, 4), 5);
        let mut b = random_sequence(7, UVec2::new(3, 4), 5);
        for _ in 0..16 {
            assert_eq!(random_next(&mut a).to_bits(), random_next(&mut b).to_bits());
        }
    }

    #[test]
    fn neighbouring_pixels_samples_and_seeds_differ() {
        let first = |seed, x, y, s| random_next(&mut random_sequence(seed, UVec2::new(x, y), s));
        let base = first(0, 10, 10, 0);
        for other in [first(1, 10, 10, 0), first(0, 11, 10, 0), first(0, 10, 11, 0), first(0, 10, 10, 1)] {
            assert_ne!(base, other);
        }
        // x and y are hashed apart: the transposed pixel is another stream.
        assert_ne!(first(0, 1, 2, 0), first(0, 2, 1, 0));
    }

    #[test]
    fn numbers_are_uniform_in_the_unit_interval() {
        // Chi-square over 64 bins of 64 draws each from 1024 pixels: 63 degrees of freedom,
        // whose 99.9th percentile is 103.4.
        const BINS: usize = 64;
        let mut counts = [0u32; BINS];
        let mut draws = 0;
        for pixel in 0..1024 {
            let mut sequence = random_sequence(3, UVec2::new(pixel % 32, pixel / 32), 0);
            for _ in 0..64 {
                let u = random_next(&mut sequence);
                assert!((0.0..1.0).contains(&u));
                counts[(u * BINS as f32) as usize] += 1;
                draws += 1;
            }
        }
        let expected = draws as f64 / BINS as f64;
        let chi_square: f64 = counts.iter().map(|&c| (c as f64 - expected).powi(2) / expected).sum();
        assert!(chi_square < 103.4, "chi-square {chi_square}");
    }

    #[test]
    fn successive_dimensions_are_uncorrelated() {
        let mut sum = 0.0f64;
        let count = 20_000;
        for sample in 0..count {
            let mut sequence = random_sequence(0, UVec2::ZERO, sample);
            let pair = random_next2(&mut sequence);
            sum += f64::from((pair.x - 0.5) * (pair.y - 0.5));
        }
        // The product of two independent uniforms centred has variance 1/144: 5 sigma.
        let bound = 5.0 * (1.0 / 144.0 / count as f64).sqrt();
        assert!((sum / count as f64).abs() < bound);
    }
}
