//! How long each frame of a scripted run took to draw, printed when the run ends: the render
//! and its presentation (on the direct path one submission; a frame's GPU work may finish in
//! the next frame's wait, as one frame is in flight). `--frames` runs are how the backends'
//! frame times are measured from the command line.

use std::time::Duration;

#[derive(Default)]
pub(crate) struct RenderTimes {
    times: Vec<Duration>,
}

impl RenderTimes {
    pub(crate) fn record(&mut self, time: Duration) {
        self.times.push(time);
    }

    /// `frame time over N frames: median, mean, min and max in ms`; `None` before any frame.
    pub(crate) fn summary(&self) -> Option<String> {
        let mut sorted = self.times.clone();
        sorted.sort_unstable();
        let (first, last) = (sorted.first()?, sorted.last()?);
        let count = sorted.len();
        let median =
            if count % 2 == 1 { sorted[count / 2] } else { (sorted[count / 2 - 1] + sorted[count / 2]) / 2 };
        let mean = sorted.iter().sum::<Duration>() / count as u32;
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        Some(format!(
            "frame time (render + present) over {count} frames: median {:.2} ms, mean {:.2} ms, min {:.2} ms, max {:.2} ms",
            ms(median),
            ms(mean),
            ms(*first),
            ms(*last)
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nothing_to_say_before_a_frame() {
        assert_eq!(RenderTimes::default().summary(), None);
    }

    #[test]
    fn summary_is_median_mean_min_max() {
        let mut times = RenderTimes::default();
        for ms in [40, 10, 20, 30] {
            times.record(Duration::from_millis(ms));
        }
        assert_eq!(
            times.summary().unwrap(),
            "frame time (render + present) over 4 frames: median 25.00 ms, mean 25.00 ms, min 10.00 ms, max 40.00 ms"
        );
        times.record(Duration::from_millis(1));
        assert!(times.summary().unwrap().contains("over 5 frames: median 20.00 ms, mean 20.20 ms"));
    }
}
