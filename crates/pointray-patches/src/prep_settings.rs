//! Every setting `prep` takes, whichever route it comes by (the command-line flags, a scene
//! file's `prep` table, code): one type, checked in one place
//! (`PrepSettings::check`) and recorded whole in the patch store's header.

use glam::DVec3;
use serde::{Deserialize, Deserializer};

/// The settings `prep` runs with. In a scene file it is the `prep` table of a points object,
/// with the command-line flags' names; a key left out keeps its default.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PrepSettings {
    /// Neighbours used for the support radius and the quadratic fit (METHOD.md §2.1).
    pub k: u32,
    /// Neighbours used for the PCA normal (METHOD.md §2.2).
    pub normal_k: u32,
    /// Compute PCA normals even when the input carries normals.
    pub recompute_normals: bool,
    /// Orient normals toward this point (input coordinates); overrides the cloud's own
    /// sensor position.
    #[serde(deserialize_with = "position")]
    pub sensor: Option<DVec3>,
    /// Drop statistical outliers before fitting; `None` keeps every point.
    pub remove_outliers: Option<OutlierFilter>,
    /// How the support radius `d_i` is chosen where the scan structure is not used.
    pub radius: RadiusMode,
    /// How far each patch reaches, as a fraction of the chosen `d_i`: the stored radius, and
    /// so the disk, the box and the self-clearance, is `disk_scale d_i`. The fit still uses
    /// the whole neighbourhood. 1 is the paper.
    pub disk_scale: f32,
    /// The box each patch gets (METHOD.md §2.4).
    pub boxes: BoxKind,
    /// Whether a LiDAR scan's line structure shapes the patches.
    pub scan: ScanMode,
    /// Points closer than this many f32 ulps at their own recentred coordinates are merged as
    /// duplicates (`pointray_surface::duplicates`): what f32 barely tells apart there. Not the
    /// cloud's extent, which one stray point far off would blow up. Not a flag: the tolerance
    /// follows from f32, not from the data.
    #[serde(skip)]
    pub duplicate_tolerance: f32,
}

impl Default for PrepSettings {
    fn default() -> Self {
        Self {
            k: 9,
            normal_k: 16,
            recompute_normals: false,
            sensor: None,
            remove_outliers: None,
            radius: RadiusMode::Cell,
            disk_scale: 1.0,
            boxes: BoxKind::Tight,
            scan: ScanMode::Auto,
            duplicate_tolerance: 1.0,
        }
    }
}

/// Whether `prep` uses a LiDAR scan's structure (`scan::lines`): scan lines from a ring field
/// or recovered from elevations, seen from a known sensor.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ScanMode {
    /// Scan-aware patches whenever the sensor is known and its lines can be found.
    #[default]
    Auto,
    /// Every cloud as unstructured points.
    Off,
}

impl ScanMode {
    /// The code stored in the patch store's header.
    pub fn code(self) -> u32 {
        match self {
            Self::Auto => 0,
            Self::Off => 1,
        }
    }

    pub fn from_code(code: u32) -> Option<Self> {
        match code {
            0 => Some(Self::Auto),
            1 => Some(Self::Off),
            _ => None,
        }
    }
}

/// Fewer neighbours than this cannot give a PCA normal or a plane fit.
pub const MIN_NEIGHBOURS: u32 = 3;

/// More neighbours than this no longer describe a local surface, and the neighbour search
/// grows with k squared.
pub const MAX_NEIGHBOURS: u32 = 1024;

/// Beyond this, patches reach past twice their farthest neighbour: no longer local.
const MAX_DISK_SCALE: f32 = 2.0;

impl PrepSettings {
    /// Every prep setting, whichever route it came by (flags, a scene file, code): the one place
    /// they are checked.
    pub fn check(&self) -> Result<(), InvalidSetting> {
        for (name, value) in [("k", self.k), ("normal_k", self.normal_k)] {
            if !(MIN_NEIGHBOURS..=MAX_NEIGHBOURS).contains(&value) {
                return invalid(
                    name,
                    format!("must be between {MIN_NEIGHBOURS} and {MAX_NEIGHBOURS}, got {value}"),
                );
            }
        }
        if !(self.duplicate_tolerance >= 0.0 && self.duplicate_tolerance.is_finite()) {
            return invalid(
                "duplicate_tolerance",
                format!("must be finite and >= 0, got {}", self.duplicate_tolerance),
            );
        }
        if !(self.disk_scale > 0.0 && self.disk_scale <= MAX_DISK_SCALE) {
            return invalid(
                "disk_scale",
                format!("must be in (0, {MAX_DISK_SCALE}], got {}", self.disk_scale),
            );
        }
        if let Some(sensor) = self.sensor.filter(|sensor| !sensor.is_finite()) {
            return invalid("sensor", format!("must be a finite position, got {sensor}"));
        }
        if let Some(filter) = &self.remove_outliers {
            check_outlier_filter(filter)?;
        }
        Ok(())
    }
}

fn check_outlier_filter(filter: &OutlierFilter) -> Result<(), InvalidSetting> {
    let OutlierFilter { neighbors, sigmas } = *filter;
    if !(1..=MAX_NEIGHBOURS).contains(&neighbors) {
        return invalid(
            "remove_outliers.neighbors",
            format!("must be between 1 and {MAX_NEIGHBOURS}, got {neighbors}"),
        );
    }
    if !(sigmas.is_finite() && sigmas >= 0.0) {
        return invalid("remove_outliers.sigmas", format!("must be a finite number >= 0, got {sigmas}"));
    }
    Ok(())
}

/// A setting out of its range: which one, and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("invalid setting `{setting}`: {problem}")]
pub struct InvalidSetting {
    pub setting: &'static str,
    pub problem: String,
}

fn invalid(setting: &'static str, problem: String) -> Result<(), InvalidSetting> {
    Err(InvalidSetting { setting, problem })
}

/// `sensor = [x, y, z]`.
fn position<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Option<DVec3>, D::Error> {
    Ok(Some(DVec3::from_array(<[f64; 3]>::deserialize(deserializer)?)))
}

/// How `prep` chooses each patch's support radius `d_i`.
///
/// The default is the cell radius: against the paper's on the bunny and horse scans it halves
/// the false surface at silhouettes and the normal error, and shortens the GPU frame by 8–26%.
/// It leaves no pinholes: the few pixels in 100,000 that the mesh covers and it does not all
/// lie on the mesh's silhouette, where the paper's larger disks bulge past it instead
/// (bench/FIDELITY.md, "Cell margin").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RadiusMode {
    /// METHOD.md §2.3: the tangential distance to the farthest of the `k` neighbours.
    Paper,
    /// The paper's radius widened to cover the point's Voronoi cell and held to a band
    /// around the neighbourhood's median.
    Adaptive,
    /// Just what covers the point's Voronoi cell, `CELL_MARGIN` times its farthest corner,
    /// and never more than the paper's radius.
    #[default]
    Cell,
}

impl RadiusMode {
    /// The code stored in the patch store's header.
    pub fn code(self) -> u32 {
        match self {
            Self::Paper => 0,
            Self::Adaptive => 1,
            Self::Cell => 2,
        }
    }

    pub fn from_code(code: u32) -> Option<Self> {
        match code {
            0 => Some(Self::Paper),
            1 => Some(Self::Adaptive),
            2 => Some(Self::Cell),
            _ => None,
        }
    }
}

/// The settings of the filter (PCL's `StatisticalOutlierRemoval`, with the same meaning).
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutlierFilter {
    /// `K`: how many nearest neighbours each point's mean distance is taken over.
    pub neighbors: u32,
    /// `N`: how many standard deviations above the mean a point's mean distance may be.
    pub sigmas: f32,
}

/// Which box each patch gets.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BoxKind {
    /// The cube of half-size `d_i` around the patch's origin, as in the paper.
    Cube,
    /// The box around the patch surface `w = f(u, v)` over its support ellipse: the
    /// default, since every hit the disk test accepts lies inside it (the same hits as the
    /// cube's, bench/FIDELITY.md) and rays test fewer boxes (bench/RESULTS.md).
    #[default]
    Tight,
}

impl BoxKind {
    /// The code stored in the patch store's header.
    pub fn code(self) -> u32 {
        match self {
            BoxKind::Cube => 0,
            BoxKind::Tight => 1,
        }
    }

    pub fn from_code(code: u32) -> Option<Self> {
        match code {
            0 => Some(BoxKind::Cube),
            1 => Some(BoxKind::Tight),
            _ => None,
        }
    }
}
