//! Frames per second and frame time, for the window title.

use std::time::{Duration, Instant};

/// How often the title is refreshed.
const WINDOW: Duration = Duration::from_millis(500);

pub(crate) struct FrameStats {
    window_start: Instant,
    frames_in_window: u32,
    busy_in_window: Duration,
}

impl FrameStats {
    pub(crate) fn new(now: Instant) -> Self {
        Self { window_start: now, frames_in_window: 0, busy_in_window: Duration::ZERO }
    }

    /// Records a frame that took `frame_time` to render and present; every half second
    /// returns (frames per second, mean frame time) over that half second.
    pub(crate) fn record(&mut self, now: Instant, frame_time: Duration) -> Option<(f64, Duration)> {
        self.frames_in_window += 1;
        self.busy_in_window += frame_time;
        let elapsed = now.duration_since(self.window_start);
        if elapsed < WINDOW {
            return None;
        }
        let fps = self.frames_in_window as f64 / elapsed.as_secs_f64();
        let mean = self.busy_in_window / self.frames_in_window;
        *self = Self::new(now);
        Some((fps, mean))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reports_rate_and_mean_after_half_a_second() {
        let start = Instant::now();
        let mut stats = FrameStats::new(start);
        assert_eq!(stats.record(start + Duration::from_millis(100), Duration::from_millis(10)), None);
        let (fps, mean) =
            stats.record(start + Duration::from_millis(500), Duration::from_millis(30)).unwrap();
        assert!((fps - 4.0).abs() < 1e-9);
        assert_eq!(mean, Duration::from_millis(20));
    }
}
