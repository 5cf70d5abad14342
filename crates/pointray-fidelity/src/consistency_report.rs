//! What a sensor-ray consistency run reports, as text and JSON.

use std::fmt;
use std::path::{Path, PathBuf};

use pointray_patches::PatchSet;
use serde::Serialize;

use crate::FidelityError;
use crate::beam_spacing::{SUPPORT_LIMIT, SupportReport};
use crate::percentile::percentile;
use crate::range_tolerance::{RangeTolerance, SPACING_NEIGHBOR};
use crate::report_json::write_json;
use crate::sensor_pixel_consistency::PixelConsistency;
use crate::sensor_ray_consistency::{ConsistencyOptions, RayOutcome};

/// The outcomes of the rays cast.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ConsistencyCounts {
    /// Rays cast (returns at their own sensor's position have no ray and are left out).
    pub rays: usize,
    pub consistent: usize,
    /// Of the consistent, the rays that met the return's own surface early (`RayOutcome::
    /// MetOwnSurfaceEarly`).
    pub met_own_surface_early: usize,
    /// Floaters: surface well before the return.
    pub occluded_in_front: usize,
    /// Holes: surface well beyond the return, or none.
    pub passed_through: usize,
    /// Of the holes, the rays that met no surface at all.
    pub missed: usize,
    /// The median of the rays' tolerances, in the cloud's units.
    pub tolerance_median: Option<f64>,
}

impl ConsistencyCounts {
    /// Counts the outcomes, each with its ray's tolerance; `None` where no ray was cast.
    pub fn of(checked: &[Option<(RayOutcome, f64)>]) -> Self {
        let mut counts = Self::default();
        let mut tolerances = Vec::with_capacity(checked.len());
        for &(outcome, tolerance) in checked.iter().flatten() {
            counts.rays += 1;
            tolerances.push(tolerance as f32);
            match outcome {
                RayOutcome::Consistent => counts.consistent += 1,
                RayOutcome::MetOwnSurfaceEarly => {
                    counts.consistent += 1;
                    counts.met_own_surface_early += 1;
                }
                RayOutcome::OccludedInFront => counts.occluded_in_front += 1,
                RayOutcome::PassedThrough { missed } => {
                    counts.passed_through += 1;
                    counts.missed += usize::from(missed);
                }
            }
        }
        counts.tolerance_median = percentile(&mut tolerances, 0.5).map(f64::from);
        counts
    }

    fn fraction(&self, count: usize) -> Option<f64> {
        (self.rays > 0).then(|| count as f64 / self.rays as f64)
    }
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConsistencyReport {
    pub points_file: Option<PathBuf>,
    /// Points in the file, each a return.
    pub returns: usize,
    pub patches: usize,
    pub acceptance: &'static str,
    /// A return agrees with the surface when the first hit along its ray lies within the
    /// largest of these terms of its range.
    pub tolerance: RangeTolerance,
    /// The local spacing is the distance to this nearest other return.
    pub spacing_neighbor: usize,
    pub counts: ConsistencyCounts,
    /// Fractions of the rays cast; `None` when none was.
    pub consistent_fraction: Option<f64>,
    pub occluded_in_front_fraction: Option<f64>,
    pub passed_through_fraction: Option<f64>,
    /// The dense check: each return's pixel on an angular grid around its sensor.
    pub pixels: PixelConsistency,
    /// The patches' support against the beam spacing, when the points carry rings.
    pub support: Option<SupportReport>,
    /// Wall-clock time of the neighbour search and the rays.
    pub seconds: f64,
}

impl ConsistencyReport {
    pub(crate) fn new(
        returns: usize,
        patches: &PatchSet,
        options: &ConsistencyOptions,
        counts: ConsistencyCounts,
        pixels: PixelConsistency,
        seconds: f64,
    ) -> Self {
        Self {
            points_file: None,
            returns,
            patches: patches.len(),
            acceptance: options.acceptance.name(),
            tolerance: options.tolerance,
            spacing_neighbor: SPACING_NEIGHBOR,
            consistent_fraction: counts.fraction(counts.consistent),
            occluded_in_front_fraction: counts.fraction(counts.occluded_in_front),
            passed_through_fraction: counts.fraction(counts.passed_through),
            counts,
            pixels,
            support: None,
            seconds,
        }
    }

    /// Writes the report as pretty-printed JSON, atomically.
    pub fn write_json(&self, path: &Path) -> Result<(), FidelityError> {
        write_json(self, path)
    }
}

impl fmt::Display for ConsistencyReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let percent = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{:.3} %", v * 100.0));
        let (counts, tolerance) = (&self.counts, &self.tolerance);
        writeln!(
            f,
            "{} rays of {} returns against {} patches (acceptance {}), {:.1} s",
            counts.rays, self.returns, self.patches, self.acceptance, self.seconds
        )?;
        writeln!(
            f,
            "tolerance: max({}, {} x range, {} x distance to the {}th nearest return), median {}",
            tolerance.absolute,
            tolerance.range_fraction,
            tolerance.spacing_multiple,
            self.spacing_neighbor,
            counts.tolerance_median.map_or("-".to_owned(), |t| format!("{t:.4}"))
        )?;
        writeln!(
            f,
            "consistent:          {} ({} rays met the return's own surface early)",
            percent(self.consistent_fraction),
            counts.met_own_surface_early
        )?;
        writeln!(f, "occluded in front:   {} (floaters)", percent(self.occluded_in_front_fraction))?;
        writeln!(
            f,
            "passed through:      {} (holes; {} rays met nothing)",
            percent(self.passed_through_fraction),
            counts.missed
        )?;
        let pixels = &self.pixels;
        writeln!(
            f,
            "from the sensor's pixels ({}°, tolerance max({} m, {} x range)): {} consistent, {} holes, {} floaters",
            pixels.pixel_degrees,
            pixels.absolute_tolerance,
            pixels.range_tolerance,
            percent(pixels.consistent_fraction),
            percent(pixels.hole_fraction),
            percent(pixels.floater_fraction)
        )?;
        match &self.support {
            Some(s) => write!(
                f,
                "support / beam spacing: max {:.2}, p99 {:.2}, {:.3} % over {SUPPORT_LIMIT} ({} patches, {} rings)",
                s.max_ratio,
                s.p99_ratio,
                s.over_limit_fraction * 100.0,
                s.patches,
                s.rings
            ),
            None => write!(f, "support / beam spacing: not measured (the points carry no rings)"),
        }
    }
}
