//! Whether a patch set can be handed to a renderer: records that agree in number, and every
//! number finite and within `geometry_range`. A patch store can pass its checksum and still
//! hold NaN or 1e38 boxes (written by a bug, or by hand); those must be refused before a
//! bounding-volume builder sees them.

use glam::DVec3;
use pointray_kernels::{COLOR_NEIGHBORS, NO_NEIGHBOR, PatchCold, PatchHot};
use rayon::prelude::*;

use crate::geometry_range::{box_in_range, coordinates_in_range};
use crate::{PatchSet, PrepSettings};

impl PatchSet {
    /// `Ok` when the set is consistent and in range; else the first problem found.
    pub fn check(&self) -> Result<(), String> {
        let n = self.len();
        if self.aabbs.len() != n || self.cold.len() != n {
            return Err(format!(
                "{n} patches, {} boxes and {} cold records",
                self.aabbs.len(),
                self.cold.len()
            ));
        }
        check_records(&self.settings, self.offset, &self.hot, &self.cold)?;
        if let Some(i) = self.aabbs.par_iter().position_first(|aabb| !box_in_range(aabb)) {
            return Err(format!("box {i} is not finite, not ordered, or beyond the coordinate range"));
        }
        self.check_color_neighbors()
    }

    fn check_color_neighbors(&self) -> Result<(), String> {
        let n = self.len();
        if !self.color_neighbors.is_empty() && self.color_neighbors.len() != n * COLOR_NEIGHBORS {
            return Err(format!("{} colour neighbours for {n} patches", self.color_neighbors.len()));
        }
        match self.color_neighbors.par_iter().position_first(|&j| j != NO_NEIGHBOR && j as usize >= n) {
            Some(bad) => Err(format!(
                "colour neighbour {} of patch {} is {}, beyond the {n} patches",
                bad % COLOR_NEIGHBORS,
                bad / COLOR_NEIGHBORS,
                self.color_neighbors[bad]
            )),
            None => Ok(()),
        }
    }
}

/// `Ok` when the records of a set prepped with `settings` and recentred by `offset` agree in
/// number and every number is finite and in range; else the first problem found.
pub fn check_records(
    settings: &PrepSettings,
    offset: DVec3,
    hot: &[PatchHot],
    cold: &[PatchCold],
) -> Result<(), String> {
    if hot.len() != cold.len() {
        return Err(format!("{} patches and {} cold records", hot.len(), cold.len()));
    }
    if !offset.is_finite() {
        return Err(format!("the recentring offset {offset} is not finite"));
    }
    settings.check().map_err(|e| format!("stored settings: {e}"))?;
    let bad_patch = |patch: &PatchHot| {
        let patch = patch.decode();
        let [x, y, z] = patch.origin.to_array();
        !(coordinates_in_range(&[x, y, z, patch.radii.x])
            && patch.radii.x > 0.0
            && patch.radii.y.is_finite()
            && patch.coefficients.iter().all(|v| v.is_finite()))
    };
    if let Some(i) = hot.par_iter().position_first(bad_patch) {
        return Err(format!("patch {i} has a number that is not finite or is out of range"));
    }
    let bad_cold = |record: &PatchCold| {
        !(record.intensity.is_finite() && record.color_reach.is_finite() && record.color_reach >= 0.0)
    };
    if let Some(i) = cold.par_iter().position_first(bad_cold) {
        return Err(format!("cold record {i} has a non-finite intensity or colour reach"));
    }
    Ok(())
}
