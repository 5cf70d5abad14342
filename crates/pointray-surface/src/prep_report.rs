//! What `prep` did: counts and per-stage wall times.

use std::fmt;
use std::time::Duration;

use glam::DVec3;
use pointray_patches::ScanStructure;

use crate::density_radius::RadiusAdjustments;
use crate::prep_progress::Stage;
use crate::scan::lines::{MIN_LINE_RETURNS, Unstructured};

/// How many patches ended with each fit model (METHOD.md §2.6).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FitCounts {
    pub quadratic: usize,
    pub plane: usize,
    pub flat: usize,
}

/// How many support radii needed a fallback (METHOD.md §2.3).
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
    /// Points dropped by the statistical outlier filter (0 when it did not run).
    pub removed_outliers: usize,
    pub patches: usize,
    /// Input normals that were zero or not finite and were replaced by PCA normals.
    pub replaced_input_normals: usize,
    pub fits: FitCounts,
    pub radius_fallbacks: RadiusFallbacks,
    /// How the adaptive radius mode changed the paper's radii (all 0 in paper mode).
    pub radius_adjustments: RadiusAdjustments,
    /// The scan structure the patches followed, when one was used.
    pub scan: Option<ScanSummary>,
    /// Why a scan with a known sensor was prepped as unstructured points.
    pub unstructured_because: Option<Unstructured>,
    /// The recentring offset (`input = local + offset`), also stored in the patch store.
    pub offset: DVec3,
    /// For each patch, the index of the input point it was made from (patches are in
    /// Morton order, and merged duplicates have no patch of their own).
    pub patch_sources: Vec<u32>,
    /// Wall time of each stage, in the order they ran.
    pub stage_times: Vec<(Stage, Duration)>,
}

/// How a LiDAR scan's structure shaped the patches.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ScanSummary {
    /// Scan lines found (beams or grid rows, over all stations).
    pub lines: usize,
    /// Returns on lines of `MIN_LINE_RETURNS` or more.
    pub returns_on_lines: usize,
    /// Patches over a surface their neighbours agree on; the rest are small disks facing the
    /// sensor.
    pub surface_patches: usize,
}

impl PrepReport {
    /// The scan structure as the patch store records it.
    pub fn scan_structure(&self) -> ScanStructure {
        match (self.scan, self.unstructured_because) {
            (Some(ScanSummary { lines, returns_on_lines, surface_patches }), _) => ScanStructure::Lines {
                lines: lines as u64,
                returns_on_lines: returns_on_lines as u64,
                patches: self.patches as u64,
                surface_patches: surface_patches as u64,
            },
            (None, Some(reason)) => ScanStructure::Unstructured { reason: reason.to_string() },
            (None, None) => ScanStructure::NotSought,
        }
    }

    pub fn total_time(&self) -> Duration {
        self.stage_times.iter().map(|(_, time)| *time).sum()
    }
}

impl fmt::Display for PrepReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} points in, {} duplicates merged, {} outliers removed, {} patches",
            self.input_points, self.merged_duplicates, self.removed_outliers, self.patches
        )?;
        // f64's Display is the shortest text that parses back to the same number: the
        // printed offset is exactly the stored one.
        let DVec3 { x, y, z } = self.offset;
        writeln!(f, "recentring offset (input = local + offset): {x}, {y}, {z}")?;
        let FitCounts { quadratic, plane, flat } = self.fits;
        writeln!(f, "fits: {quadratic} quadratic, {plane} plane, {flat} flat")?;
        let RadiusFallbacks { distance, spacing } = self.radius_fallbacks;
        writeln!(f, "support radius fallbacks: {distance} to |v|, {spacing} to the spacing")?;
        let RadiusAdjustments { widened, capped, raised } = self.radius_adjustments;
        if widened + capped + raised > 0 {
            writeln!(f, "adaptive radii: {widened} widened to their cell, {capped} capped, {raised} raised")?;
        }
        if let Some(ScanSummary { lines, returns_on_lines, surface_patches }) = self.scan {
            let disks = self.patches - surface_patches;
            let share = 100.0 * returns_on_lines as f64 / self.patches.max(1) as f64;
            writeln!(
                f,
                "scan-aware: {lines} scan lines ({share:.1} % of returns on lines of {MIN_LINE_RETURNS} or more), \
                 {surface_patches} surface patches, {disks} footprint disks"
            )?;
        }
        if let Some(reason) = self.unstructured_because {
            writeln!(f, "scan structure not used, so the patches are unstructured: {reason}")?;
        }
        if self.replaced_input_normals > 0 {
            writeln!(f, "input normals replaced: {}", self.replaced_input_normals)?;
        }
        for (stage, time) in &self.stage_times {
            writeln!(f, "  {:<22} {:>9.3} s", stage.name(), time.as_secs_f64())?;
        }
        write!(f, "  {:<22} {:>9.3} s", "total", self.total_time().as_secs_f64())
    }
}
