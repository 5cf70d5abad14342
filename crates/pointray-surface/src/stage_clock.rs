//! Times each stage of `prep` and reports it to its progress.

use std::time::{Duration, Instant};

use crate::prep_progress::{PrepProgress, Stage};

/// Times each stage and tells `progress` about it.
pub(crate) struct StageClock<'a> {
    pub(crate) progress: &'a dyn PrepProgress,
    pub(crate) times: Vec<(Stage, Duration)>,
}

impl StageClock<'_> {
    pub(crate) fn run<T>(&mut self, stage: Stage, items: usize, work: impl FnOnce() -> T) -> T {
        self.progress.stage_started(stage, items as u64);
        let start = Instant::now();
        let result = work();
        let elapsed = start.elapsed();
        self.progress.stage_finished(stage, elapsed);
        self.times.push((stage, elapsed));
        result
    }
}
