//! What `prep` did: counts and per-stage wall times.

use std::fmt;
use std::time::Duration;

use crate::prep_progress::Stage;

/// How many patches ended with each fit model (SPEC.md §2.6).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FitCounts {
    pub quadratic: usize,
    pub plane: usize,
    pub flat: usize,
}

/// How many support radii needed a fallback (SPEC.md §2.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RadiusFallbacks {
    /// `|v|` instead of its tangential length.
    pub distance: usize,
    /// A fraction of the mean neighbour spacing.
    pub spacing: usize,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct PrepReport {
    pub input_points: usize,
    pub merged_duplicates: usize,
    pub patches: usize,
    /// Input normals that were zero or not finite and were replaced by PCA normals.
    pub replaced_input_normals: usize,
    pub fits: FitCounts,
    pub radius_fallbacks: RadiusFallbacks,
    /// For each patch, the index of the input point it was made from (patches are in
    /// Morton order, and merged duplicates have no patch of their own).
    pub patch_sources: Vec<u32>,
    /// Wall time of each stage, in the order they ran.
    pub stage_times: Vec<(Stage, Duration)>,
}

impl PrepReport {
    pub fn total_time(&self) -> Duration {
        self.stage_times.iter().map(|(_, time)| *time).sum()
    }
}

impl fmt::Display for PrepReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} points in, {} duplicates merged, {} patches",
            self.input_points, self.merged_duplicates, self.patches
        )?;
        let FitCounts { quadratic, plane, flat } = self.fits;
        writeln!(f, "fits: {quadratic} quadratic, {plane} plane, {flat} flat")?;
        let RadiusFallbacks { distance, spacing } = self.radius_fallbacks;
        writeln!(f, "support radius fallbacks: {distance} to |v|, {spacing} to the spacing")?;
        if self.replaced_input_normals > 0 {
            writeln!(f, "input normals replaced: {}", self.replaced_input_normals)?;
        }
        for (stage, time) in &self.stage_times {
            writeln!(f, "  {:<22} {:>9.3} s", stage.name(), time.as_secs_f64())?;
        }
        write!(f, "  {:<22} {:>9.3} s", "total", self.total_time().as_secs_f64())
    }
}
