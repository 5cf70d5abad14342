//! The process's peak resident memory (Linux `VmHWM`), per `prep` stage: what bounds the
//! largest cloud a machine can prep. Elsewhere the readings are `None`.

use std::sync::Mutex;
use std::time::Duration;

use crate::prep_progress::{PrepProgress, Stage};

/// The highest resident set size of this process since it started or since the last
/// `reset_peak_rss`, in bytes; `None` where `/proc/self/status` has no `VmHWM`.
pub fn peak_rss() -> Option<u64> {
    status_bytes("VmHWM:")
}

/// The resident set size now, in bytes.
pub fn current_rss() -> Option<u64> {
    status_bytes("VmRSS:")
}

/// Starts a new peak from the current resident set (`/proc/self/clear_refs`); whether the
/// kernel allowed it.
pub fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

fn status_bytes(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|line| line.starts_with(field))?;
    let kib: u64 = line[field.len()..].trim().strip_suffix("kB")?.trim().parse().ok()?;
    Some(kib * 1024)
}

/// Progress that records each stage's peak resident memory (and passes everything on to
/// `inner`): the peak is reset as a stage starts and read as it finishes. Stages run one
/// at a time, so each reading is that stage's own peak, all of the process's memory
/// included. What is allocated between stages counts toward the overall peak.
pub struct StagePeaks<'a> {
    inner: &'a dyn PrepProgress,
    peaks: Mutex<Vec<(Stage, u64)>>,
    between_stages: Mutex<u64>,
}

impl<'a> StagePeaks<'a> {
    /// Starts measuring now: what the process reached before does not count.
    pub fn new(inner: &'a dyn PrepProgress) -> Self {
        reset_peak_rss();
        Self { inner, peaks: Mutex::new(Vec::new()), between_stages: Mutex::new(0) }
    }

    /// Each finished stage and its peak resident bytes, in the order they ran.
    pub fn peaks(&self) -> Vec<(Stage, u64)> {
        self.peaks.lock().map(|peaks| peaks.clone()).unwrap_or_default()
    }

    /// The highest resident bytes seen in any stage or between two.
    pub fn overall(&self) -> Option<u64> {
        let between = self.between_stages.lock().map(|bytes| *bytes).unwrap_or(0);
        self.peaks().iter().map(|&(_, bytes)| bytes).chain([between]).max().filter(|&bytes| bytes > 0)
    }
}

impl PrepProgress for StagePeaks<'_> {
    fn stage_started(&self, stage: Stage, items: u64) {
        if let (Some(bytes), Ok(mut between)) = (peak_rss(), self.between_stages.lock()) {
            *between = (*between).max(bytes);
        }
        reset_peak_rss();
        self.inner.stage_started(stage, items);
    }

    fn advanced(&self, items: u64) {
        self.inner.advanced(items);
    }

    fn stage_finished(&self, stage: Stage, elapsed: Duration) {
        if let (Some(bytes), Ok(mut peaks)) = (peak_rss(), self.peaks.lock()) {
            peaks.push((stage, bytes));
        }
        self.inner.stage_finished(stage, elapsed);
    }
}
