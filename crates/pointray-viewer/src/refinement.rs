//! Progressive refinement while the view is still. The render settings have no sample offset
//! (the contract's jitter sequence always starts at sample 0), so each pass renders the whole
//! image again with twice the samples of the last, and the newest pass is shown: the shown
//! image is the mean of 1, 2, 4 ... 16 times the base samples per pixel.
//! The CPU renderer also renders previews at reduced resolution while the view moves.

use std::time::{Duration, Instant};

/// Doublings after the first full pass: up to 16 times the base samples.
const MAX_LEVEL: u32 = 4;
/// The view counts as still this long after its last change.
const SETTLE: Duration = Duration::from_millis(250);
/// Previews are this many times smaller on each side.
pub(crate) const PREVIEW_DIVISOR: u32 = 3;

/// One render to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Pass {
    pub(crate) samples_per_pixel: u32,
    /// The image is rendered at the window's size divided by this.
    pub(crate) divisor: u32,
}

pub(crate) struct Refinement {
    base_samples: u32,
    level: u32,
    last_change: Instant,
}

impl Refinement {
    pub(crate) fn new(base_samples: u32, now: Instant) -> Self {
        Self { base_samples: base_samples.max(1), level: 0, last_change: now }
    }

    pub(crate) fn restart(&mut self, now: Instant) {
        self.level = 0;
        self.last_change = now;
    }

    pub(crate) fn done(&self) -> bool {
        self.level > MAX_LEVEL
    }

    /// The next pass, or `None` once the image is fully refined.
    pub(crate) fn next(&mut self, now: Instant, previews: bool) -> Option<Pass> {
        if previews && now.duration_since(self.last_change) < SETTLE {
            return Some(Pass { samples_per_pixel: self.base_samples, divisor: PREVIEW_DIVISOR });
        }
        if self.done() {
            return None;
        }
        let pass = Pass { samples_per_pixel: self.base_samples << self.level, divisor: 1 };
        self.level += 1;
        Some(pass)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn still_view_doubles_samples_then_stops() {
        let start = Instant::now();
        let mut refinement = Refinement::new(1, start);
        let samples: Vec<u32> =
            std::iter::from_fn(|| refinement.next(start, false)).map(|p| p.samples_per_pixel).collect();
        assert_eq!(samples, vec![1, 2, 4, 8, 16]);
        refinement.restart(start);
        assert_eq!(refinement.next(start, false), Some(Pass { samples_per_pixel: 1, divisor: 1 }));
    }

    #[test]
    fn moving_cpu_view_gets_previews_until_it_settles() {
        let start = Instant::now();
        let mut refinement = Refinement::new(2, start);
        assert_eq!(
            refinement.next(start, true),
            Some(Pass { samples_per_pixel: 2, divisor: PREVIEW_DIVISOR })
        );
        let later = start + SETTLE;
        assert_eq!(refinement.next(later, true), Some(Pass { samples_per_pixel: 2, divisor: 1 }));
    }
}
