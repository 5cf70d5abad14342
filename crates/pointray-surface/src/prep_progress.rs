//! Progress reporting for `prep`, so that the CLI can drive a progress bar.

use std::fmt;
use std::time::Duration;

/// The stages of `prep`, in the order they run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stage {
    Validate,
    Recentre,
    MortonSort,
    MergeDuplicates,
    OutlierRemoval,
    Neighbours,
    ScanLines,
    /// The scan route's neighbourhoods and plane fits, in place of normals to the fit.
    ScanPatches,
    Normals,
    Orientation,
    Frames,
    SupportRadii,
    QuadraticFit,
    ColdRecords,
    Boxes,
    /// Prep in bounded memory: the first read of the input, for its bounds.
    Survey,
    /// The second read, in sorted runs written to scratch files.
    SortRuns,
    /// The runs merged into one file along the Morton curve.
    MergeRuns,
    /// A COPC file's octree read node by node into one file along the Morton curve, in
    /// place of the survey and the runs.
    SortOctree,
    /// The tiles prepped one after another, each with its halo.
    PrepTiles,
    /// The tiles' patches written as one store.
    MergeTiles,
}

impl Stage {
    pub fn name(self) -> &'static str {
        match self {
            Stage::Validate => "validate",
            Stage::Recentre => "recentre",
            Stage::MortonSort => "Morton sort",
            Stage::MergeDuplicates => "merge duplicates",
            Stage::OutlierRemoval => "outlier removal",
            Stage::Neighbours => "k nearest neighbours",
            Stage::ScanLines => "scan lines",
            Stage::ScanPatches => "scan patches",
            Stage::Normals => "normals",
            Stage::Orientation => "orientation",
            Stage::Frames => "frames",
            Stage::SupportRadii => "support radii",
            Stage::QuadraticFit => "quadratic fit",
            Stage::Boxes => "boxes",
            Stage::ColdRecords => "cold records",
            Stage::Survey => "read bounds",
            Stage::SortRuns => "sort runs",
            Stage::MergeRuns => "merge runs",
            Stage::SortOctree => "sort along the octree",
            Stage::PrepTiles => "prep tiles",
            Stage::MergeTiles => "write store",
        }
    }
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Receives `prep`'s progress. `advanced` may be called from several threads at once.
pub trait PrepProgress: Sync {
    /// `stage` begins and will process `items` points.
    fn stage_started(&self, stage: Stage, items: u64);
    /// `items` more points of the current stage are done.
    fn advanced(&self, items: u64);
    /// `stage` is done after `elapsed`.
    fn stage_finished(&self, stage: Stage, elapsed: Duration);
}

/// Progress that goes nowhere.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl PrepProgress for NoProgress {
    fn stage_started(&self, _stage: Stage, _items: u64) {}
    fn advanced(&self, _items: u64) {}
    fn stage_finished(&self, _stage: Stage, _elapsed: Duration) {}
}
