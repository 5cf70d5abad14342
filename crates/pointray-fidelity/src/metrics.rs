//! The numbers reported for one view or for all views pooled.

use serde::Serialize;

use crate::PixelComparison;
use crate::percentile::percentile;

/// Every rate is a fraction of the pixels the mesh covers. A statistic over no samples (no
/// mesh pixels, no pixel both hit) is `None` (`null` in JSON).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FidelityMetrics {
    pub mesh_pixels: u64,
    pub both_hit_pixels: u64,
    /// Pixels the mesh covers but the points miss.
    pub hole_rate: Option<f64>,
    /// Of those, the ones inside the mesh's image (all eight neighbours covered): pinholes
    /// through the surface rather than a silhouette a pixel narrower.
    pub pinhole_rate: Option<f64>,
    /// Mesh pixels the scan's sensor could have seen (`None` without a sensor), and the
    /// fraction of them the points miss: the hole rate that measures the surface, not where
    /// the sensor never looked.
    pub seen_mesh_pixels: Option<u64>,
    pub seen_hole_rate: Option<f64>,
    /// Pixels the points cover but the mesh misses.
    pub false_surface_rate: Option<f64>,
    /// `|d_points - d_mesh|` over the mesh's bounding-box diagonal, at pixels both hit.
    pub depth_error_mean: Option<f64>,
    pub depth_error_p99: Option<f64>,
    /// Unsigned normal angle in degrees, at pixels both hit.
    pub normal_error_mean_degrees: Option<f64>,
    pub normal_error_p95_degrees: Option<f64>,
    /// PSNR of the shaded images (colours clamped to [0, 1]); `None` when they are identical.
    pub psnr_db: Option<f64>,
}

impl PixelComparison {
    pub fn metrics(&self) -> FidelityMetrics {
        let rate = |count: u64| (self.mesh_pixels > 0).then(|| count as f64 / self.mesh_pixels as f64);
        FidelityMetrics {
            mesh_pixels: self.mesh_pixels,
            both_hit_pixels: self.depth_errors.len() as u64,
            hole_rate: rate(self.hole_pixels),
            pinhole_rate: rate(self.pinhole_pixels),
            seen_mesh_pixels: self.seen.map(|seen| seen.mesh_pixels),
            seen_hole_rate: self
                .seen
                .filter(|seen| seen.mesh_pixels > 0)
                .map(|seen| seen.hole_pixels as f64 / seen.mesh_pixels as f64),
            false_surface_rate: rate(self.false_surface_pixels),
            depth_error_mean: mean(&self.depth_errors),
            depth_error_p99: percentile(&mut self.depth_errors.clone(), 0.99).map(f64::from),
            normal_error_mean_degrees: mean(&self.normal_errors_degrees),
            normal_error_p95_degrees: percentile(&mut self.normal_errors_degrees.clone(), 0.95)
                .map(f64::from),
            psnr_db: self.psnr_db(),
        }
    }

    fn psnr_db(&self) -> Option<f64> {
        let mean_squared_error = self.squared_color_error / self.color_samples.max(1) as f64;
        (mean_squared_error > 0.0).then(|| -10.0 * mean_squared_error.log10())
    }
}

fn mean(values: &[f32]) -> Option<f64> {
    (!values.is_empty()).then(|| values.iter().map(|&v| f64::from(v)).sum::<f64>() / values.len() as f64)
}
