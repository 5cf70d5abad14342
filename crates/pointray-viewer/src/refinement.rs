//! Progressive refinement while the view is still. Each pass takes the samples after those
//! already taken (`RenderSettings::first_sample`), and the window shows the mean of all of
//! them: the GPU keeps the running sums for the direct path, the host for the CPU renderer.
//! Passes grow (1, 1, 2, 4 ... times the base samples, then at most `MAX_PASS_GROWTH`
//! times) so that the first image comes at once and later ones keep the device busy without
//! stalling the window. Any change restarts from sample 0.
//! The CPU renderer also renders previews at reduced resolution while the view moves.

use std::time::{Duration, Instant};

/// The largest pass, in base samples.
const MAX_PASS_GROWTH: u32 = 16;
/// Refinement stops here: beyond it an f32 sum gains too little from one more sample.
pub(crate) const MAX_SAMPLES: u32 = 1 << 16;
/// The view counts as still this long after its last change.
const SETTLE: Duration = Duration::from_millis(250);
/// Previews are this many times smaller on each side.
pub(crate) const PREVIEW_DIVISOR: u32 = 3;

/// One render to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Pass {
    pub(crate) first_sample: u32,
    pub(crate) samples_per_pixel: u32,
    /// The image is rendered at the window's size divided by this.
    pub(crate) divisor: u32,
}

pub(crate) struct Refinement {
    base_samples: u32,
    /// Samples a pixel taken since the last change.
    taken: u32,
    last_change: Instant,
}

impl Refinement {
    pub(crate) fn new(base_samples: u32, now: Instant) -> Self {
        Self { base_samples: base_samples.max(1), taken: 0, last_change: now }
    }

    pub(crate) fn restart(&mut self, now: Instant) {
        self.taken = 0;
        self.last_change = now;
    }

    pub(crate) fn done(&self) -> bool {
        self.taken >= MAX_SAMPLES
    }

    /// The samples a pixel that the shown image averages.
    pub(crate) fn taken(&self) -> u32 {
        self.taken
    }

    /// The next pass, or `None` once the image is fully refined.
    pub(crate) fn next(&mut self, now: Instant, previews: bool) -> Option<Pass> {
        if previews && now.duration_since(self.last_change) < SETTLE {
            return Some(Pass {
                first_sample: 0,
                samples_per_pixel: self.base_samples,
                divisor: PREVIEW_DIVISOR,
            });
        }
        if self.done() {
            return None;
        }
        Some(self.one_more())
    }

    /// The next full-size pass even when refinement is done (a screenshot on the direct path
    /// reads back a fresh pass, which adds to what is shown).
    pub(crate) fn one_more(&mut self) -> Pass {
        let samples = self.taken.clamp(self.base_samples, self.base_samples * MAX_PASS_GROWTH);
        let pass = Pass { first_sample: self.taken, samples_per_pixel: samples, divisor: 1 };
        self.taken = self.taken.saturating_add(samples);
        pass
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_still_view_takes_ever_later_samples_until_the_limit() {
        let start = Instant::now();
        let mut refinement = Refinement::new(1, start);
        let passes: Vec<Pass> = std::iter::from_fn(|| refinement.next(start, false)).collect();
        let firsts: Vec<u32> = passes.iter().take(7).map(|p| p.first_sample).collect();
        let counts: Vec<u32> = passes.iter().take(7).map(|p| p.samples_per_pixel).collect();
        assert_eq!(firsts, vec![0, 1, 2, 4, 8, 16, 32]);
        assert_eq!(counts, vec![1, 1, 2, 4, 8, 16, 16]);
        // Each pass starts where the last ended, up to the limit.
        for pair in passes.windows(2) {
            assert_eq!(pair[1].first_sample, pair[0].first_sample + pair[0].samples_per_pixel);
        }
        assert_eq!(refinement.taken(), MAX_SAMPLES);
        assert!(refinement.done());
        assert_eq!(refinement.one_more().first_sample, MAX_SAMPLES);
        refinement.restart(start);
        assert_eq!(
            refinement.next(start, false),
            Some(Pass { first_sample: 0, samples_per_pixel: 1, divisor: 1 })
        );
    }

    #[test]
    fn moving_cpu_view_gets_previews_until_it_settles() {
        let start = Instant::now();
        let mut refinement = Refinement::new(2, start);
        let preview = Pass { first_sample: 0, samples_per_pixel: 2, divisor: PREVIEW_DIVISOR };
        assert_eq!(refinement.next(start, true), Some(preview));
        assert_eq!(refinement.taken(), 0, "previews are not refinement");
        let later = start + SETTLE;
        let full = Pass { first_sample: 0, samples_per_pixel: 2, divisor: 1 };
        assert_eq!(refinement.next(later, true), Some(full));
        assert_eq!(refinement.next(later, true).map(|p| p.first_sample), Some(2));
    }
}
