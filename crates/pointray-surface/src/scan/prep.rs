//! The scan-aware route through `prep`: a LiDAR scan's lines, when they can be found, and
//! patches that follow them.

use glam::{DVec3, Vec3};
use pointray_io::PointCloud;
use pointray_kernels::PatchHot;
use pointray_patches::{PrepSettings, ScanMode};
use rayon::prelude::*;

use crate::density_radius::RadiusAdjustments;
use crate::prep_progress::Stage;
use crate::prep_report::{RadiusFallbacks, ScanSummary};
use crate::scan::lines::{ScanLines, Unstructured};
use crate::scan::patches::scan_patches;
use crate::shaped_patches::{ShapedPatches, count_fits};
use crate::stage_clock::StageClock;

/// The scan lines of the prepped points, when the mode allows and the sensor is known: `Ok`
/// when the lines can be found, else why not. `None` where no scan was to be found.
pub(crate) fn scan_structure(
    points: &[Vec3],
    cloud: &PointCloud,
    source: &[u32],
    settings: &PrepSettings,
    offset: DVec3,
) -> Option<Result<ScanLines, Unstructured>> {
    if settings.scan == ScanMode::Off {
        return None;
    }
    let sensor_of = |i: u32| settings.sensor.or_else(|| cloud.sensor_of(i as usize));
    let sensors: Vec<DVec3> =
        source.iter().map(|&i| sensor_of(i).map(|s| s - offset)).collect::<Option<_>>()?;
    let rings =
        cloud.rings.as_deref().map(|rings| source.iter().map(|&i| rings[i as usize]).collect::<Vec<u16>>());
    Some(ScanLines::new(points, &sensors, rings.as_deref()))
}

/// Patches that follow a LiDAR scan's lines (`scan::patches`).
pub(crate) fn scan_shaped(
    points: &[Vec3],
    scan: ScanLines,
    disk_scale: f32,
    clock: &mut StageClock,
) -> ShapedPatches {
    let scanned = clock.run(Stage::ScanPatches, points.len(), || scan_patches(points, &scan));
    let summary = ScanSummary {
        lines: scan.lines.len(),
        returns_on_lines: scan.returns_on_lines(),
        surface_patches: scanned.iter().filter(|p| p.on_surface).count(),
    };
    let hot = scanned
        .par_iter()
        .map(|patch| {
            PatchHot::new(patch.centre, patch.frame, patch.radii * disk_scale, patch.fit.coefficients)
        })
        .collect();
    ShapedPatches {
        hot,
        fits: count_fits(&scanned.iter().map(|patch| patch.fit.kind).collect::<Vec<_>>()),
        color_radii: scanned.iter().map(|patch| patch.radii.x).collect(),
        radius_fallbacks: RadiusFallbacks::default(),
        radius_adjustments: RadiusAdjustments::default(),
        replaced_input_normals: 0,
        scan: Some(summary),
    }
}
