//! Every setting `prep` takes, whichever route it comes by (the command-line flags, a scene
//! file's `prep` table, code): one type, checked in one place
//! (`input_validation::validate_settings`) and recorded whole in the patch store's header.

use glam::DVec3;
use serde::{Deserialize, Deserializer};

use crate::density_radius::RadiusMode;
use crate::outlier_removal::OutlierFilter;
use crate::patch_bounds::BoxKind;

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
    /// Points closer than this fraction of the bounding-box diagonal are merged as
    /// duplicates; 1e-6 is about ten f32 ulps of the recentred coordinates. Not a flag: the
    /// tolerance follows from f32, not from the data.
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
            duplicate_tolerance: 1e-6,
        }
    }
}

/// Whether `prep` uses a LiDAR scan's structure (`scan_lines`): scan lines from a ring field
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

/// `sensor = [x, y, z]`.
fn position<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Option<DVec3>, D::Error> {
    Ok(Some(DVec3::from_array(<[f64; 3]>::deserialize(deserializer)?)))
}
