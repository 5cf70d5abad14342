//! Progress bars for long `prep` runs.

use std::sync::Mutex;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};
use pointray_surface::{PrepProgress, Stage};

/// Shows a bar per stage of a large cloud; small clouds finish before a bar would help.
/// Keeps each finished stage's time, for the summary prep in tiles prints.
#[derive(Default)]
pub struct PrepBar {
    bar: Mutex<Option<ProgressBar>>,
    times: Mutex<Vec<(Stage, Duration)>>,
}

impl PrepBar {
    const MIN_POINTS_FOR_BAR: u64 = 200_000;

    /// Each finished stage and how long it took, in order.
    pub fn stage_times(&self) -> Vec<(Stage, Duration)> {
        self.times.lock().unwrap().clone()
    }
}

impl PrepProgress for PrepBar {
    fn stage_started(&self, stage: Stage, items: u64) {
        if items < Self::MIN_POINTS_FOR_BAR {
            return;
        }
        let style =
            ProgressStyle::with_template("{msg:>20} [{bar:40}] {pos}/{len} {elapsed}, about {eta} left")
                .expect("the template is valid");
        let bar = ProgressBar::new(items).with_message(stage.name()).with_style(style);
        bar.enable_steady_tick(Duration::from_millis(200));
        *self.bar.lock().unwrap() = Some(bar);
    }

    fn advanced(&self, items: u64) {
        if let Some(bar) = self.bar.lock().unwrap().as_ref() {
            bar.inc(items);
        }
    }

    fn stage_finished(&self, stage: Stage, elapsed: Duration) {
        self.times.lock().unwrap().push((stage, elapsed));
        if let Some(bar) = self.bar.lock().unwrap().take() {
            bar.finish_and_clear();
        }
    }
}
