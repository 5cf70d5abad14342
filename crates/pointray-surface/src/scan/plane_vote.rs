//! The vote among planes through a return: how many of its window's returns lie near each
//! plane, each counting less the further it rises out of the plane and the further from the
//! return it lies. Every point scores dozens of planes over dozens of returns, so the returns
//! are held coordinate by coordinate and scored a block at a time, which the compiler turns
//! into vector instructions; the arithmetic and its order are those of one return at a time.

use glam::Vec3;

use crate::scan::neighborhood::MAX_RISE;

/// Returns scored between two checks of whether a plane can still win.
const BLOCK: usize = 8;

/// A segment from the point against a plane through it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RiseAndRun {
    /// How steeply the segment rises out of the plane, less the noise. Short segments count as
    /// if half the neighbourhood's scale long: along a line, returns can lie closer together
    /// than the range noise.
    pub slope: f32,
    /// Its length within the plane.
    pub run: f32,
}

impl RiseAndRun {
    #[inline(always)]
    pub fn of(offset: Vec3, normal: Vec3, scale: f32, noise: f32) -> Self {
        let height = offset.dot(normal);
        let run = (offset - height * normal).length();
        let rise = (height.abs() - noise).max(0.0);
        Self { slope: rise / run.max(0.5 * scale).max(f32::MIN_POSITIVE), run }
    }

    /// Whether the segment lies near enough the plane for its return to be on it.
    pub fn agrees(&self) -> bool {
        self.slope <= MAX_RISE
    }

    /// What its return adds to the plane's vote: more the flatter the segment, and `nearness`.
    /// Worked out whether or not it counts, so that a block of returns takes no branch.
    #[inline(always)]
    fn vote(&self, scale: f32) -> f32 {
        let vote = (1.0 - self.slope / MAX_RISE) * nearness(self.run, scale);
        if self.agrees() { vote } else { 0.0 }
    }
}

/// How much a return `run` from the point within a plane counts toward it: all of it near the
/// point, half at the neighbourhood's `scale` (the nearest return on another line), less
/// beyond. A level plane through a return on a car's side rises within `MAX_RISE` of the road
/// metres away, which holds many more returns than the car's next line a spacing above: counted
/// alike, the road would win and the car's side would get a level patch. 1 when there is no
/// scale.
#[inline(always)]
fn nearness(run: f32, scale: f32) -> f32 {
    if scale > 0.0 { scale / (scale + run) } else { 1.0 }
}

/// A window's returns (offsets from the point) ready to vote.
pub(crate) struct PlaneVote {
    /// The offsets' coordinates, padded to whole blocks: the padding's votes are left out.
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    returns: usize,
    scale: f32,
    /// The range noise's allowance before it is projected on a plane's normal.
    noise: f32,
    ray: Vec3,
}

impl PlaneVote {
    /// `scale`: the nearest return on another line; `noise`: how far the range noise may move
    /// a return along `ray`, the point's ray.
    pub fn new(window: impl ExactSizeIterator<Item = Vec3>, scale: f32, noise: f32, ray: Vec3) -> Self {
        let returns = window.len();
        let padded = returns.next_multiple_of(BLOCK);
        let (mut x, mut y, mut z) =
            (Vec::with_capacity(padded), Vec::with_capacity(padded), Vec::with_capacity(padded));
        for offset in window {
            x.push(offset.x);
            y.push(offset.y);
            z.push(offset.z);
        }
        for values in [&mut x, &mut y, &mut z] {
            values.resize(padded, 0.0);
        }
        Self { x, y, z, returns, scale, noise, ray }
    }

    /// The segment to `offset` against the plane of `normal`.
    pub fn segment(&self, offset: Vec3, normal: Vec3) -> RiseAndRun {
        RiseAndRun::of(offset, normal, self.scale, self.projected_noise(normal))
    }

    fn projected_noise(&self, normal: Vec3) -> f32 {
        self.noise * self.ray.dot(normal).abs()
    }

    /// The plane's vote, added up return by return in the window's order; `None` once it can no
    /// longer reach `to_beat`, each return adding at most 1.
    pub fn score(&self, normal: Vec3, to_beat: f32) -> Option<f32> {
        let (scale, noise) = (self.scale, self.projected_noise(normal));
        let mut score = 0.0f32;
        let blocks =
            self.x.chunks_exact(BLOCK).zip(self.y.chunks_exact(BLOCK)).zip(self.z.chunks_exact(BLOCK));
        for (block, ((x, y), z)) in blocks.enumerate() {
            let mut votes = [0.0f32; BLOCK];
            for k in 0..BLOCK {
                votes[k] = RiseAndRun::of(Vec3::new(x[k], y[k], z[k]), normal, scale, noise).vote(scale);
            }
            let scored = ((block + 1) * BLOCK).min(self.returns);
            // In the window's order, one at a time.
            votes[..scored - block * BLOCK].iter().for_each(|vote| score += vote);
            let unscored = (self.returns - scored) as f32;
            if score + unscored < to_beat {
                return None;
            }
        }
        (score >= to_beat).then_some(score)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The vote one return at a time, as it is defined.
    fn one_by_one(window: &[Vec3], normal: Vec3, scale: f32, noise: f32) -> f32 {
        window
            .iter()
            .fold(0.0, |score, &offset| score + RiseAndRun::of(offset, normal, scale, noise).vote(scale))
    }

    #[test]
    fn blocks_add_up_to_the_vote_of_one_return_at_a_time() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut random_vector = |spread: f32| {
            Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-spread..spread),
            )
        };
        for returns in [0, 1, 7, 8, 9, 45, 64] {
            let window: Vec<Vec3> = (0..returns).map(|_| random_vector(0.05)).collect();
            let ray = random_vector(1.0).normalize();
            let vote = PlaneVote::new(window.iter().copied(), 0.2, 0.01, ray);
            for _ in 0..20 {
                let normal = (Vec3::Z + 0.2 * random_vector(1.0)).normalize();
                let expected = one_by_one(&window, normal, 0.2, 0.01 * ray.dot(normal).abs());
                assert_eq!(vote.score(normal, f32::NEG_INFINITY), Some(expected), "{returns} returns");
                assert_eq!(vote.score(normal, expected), Some(expected), "a tie still counts");
                assert_eq!(vote.score(normal, expected.next_up()), None, "{returns} returns");
            }
        }
    }
}
