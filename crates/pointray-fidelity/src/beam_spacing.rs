//! How far each patch reaches against the gap between the sensor's beams where it lies: a
//! patch much wider than that gap bridges something the sensor never saw.

use std::collections::BTreeMap;

use glam::{DVec3, Vec3};
use pointray_io::PointCloud;
use pointray_patches::PatchSet;
use pointray_surface::scan::patches::MIN_INCIDENCE_COSINE;
use serde::Serialize;

use crate::percentile::percentile;
use crate::{FidelityError, ReturnOrigins};

/// A patch reaching past this many beam spacings is suspect (and the scan-aware prep's
/// bound).
pub const SUPPORT_LIMIT: f64 = 3.0;

/// Each patch's support radius over its local beam spacing, summarised.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SupportReport {
    /// Patches measured (those at a non-zero range from their sensor).
    pub patches: usize,
    pub rings: usize,
    pub max_ratio: f64,
    pub p99_ratio: f64,
    /// The fraction of patches whose ratio exceeds `SUPPORT_LIMIT`.
    pub over_limit_fraction: f64,
}

/// For each patch of `patches` (prepped from `cloud`; `sources[i]` is patch `i`'s input
/// point, `PrepReport::patch_sources`), its support radius divided by the beam spacing on
/// its surface: the angle between its ring and the adjacent rings (the wider gap, above or
/// below, each ring's elevation being the median over its returns, seen from their sensor
/// along `up`) times its range, over the cosine of the beam's incidence on the patch (a road
/// seen at a grazing angle has its rings metres apart, and a patch must bridge them).
pub fn support_against_beam_spacing(
    cloud: &PointCloud,
    patches: &PatchSet,
    sources: &[u32],
    origins: &ReturnOrigins,
    up: Vec3,
) -> Result<SupportReport, FidelityError> {
    let rings = cloud.rings.as_deref().ok_or(FidelityError::NoRings)?;
    if rings.len() != cloud.len() {
        return Err(FidelityError::RingCount { rings: rings.len(), points: cloud.len() });
    }
    if sources.len() != patches.len() {
        return Err(FidelityError::PatchSourceCount { sources: sources.len(), patches: patches.len() });
    }
    let up = up.as_dvec3().try_normalize().ok_or(FidelityError::InvalidUp(up))?;
    let gaps = ring_gaps(cloud, rings, origins, up)?;
    let mut ratios = Vec::with_capacity(patches.len());
    for (patch, &source) in patches.hot.iter().zip(sources) {
        let source = source as usize;
        if source >= cloud.len() {
            return Err(FidelityError::PatchSourceOutOfRange { source_index: source, points: cloud.len() });
        }
        let to_patch = patch.origin().as_dvec3() + patches.offset - origins.of(source);
        let range = to_patch.length();
        let incidence_cosine =
            (to_patch.dot(patch.normal().as_dvec3()) / range).abs().max(f64::from(MIN_INCIDENCE_COSINE));
        let spacing = gaps.get(&rings[source]).copied().unwrap_or(0.0) * range / incidence_cosine;
        if spacing > 0.0 && spacing.is_finite() {
            ratios.push((f64::from(patch.radius()) / spacing) as f32);
        }
    }
    let over = ratios.iter().filter(|&&r| f64::from(r) > SUPPORT_LIMIT).count();
    Ok(SupportReport {
        patches: ratios.len(),
        rings: gaps.len(),
        max_ratio: ratios.iter().copied().fold(0.0f32, f32::max).into(),
        p99_ratio: percentile(&mut ratios, 0.99).map_or(0.0, f64::from),
        over_limit_fraction: over as f64 / ratios.len().max(1) as f64,
    })
}

/// Each ring's angular gap to its neighbours in radians: the wider of the gaps to the ring
/// above and the ring below (the one gap at the band's edges), rings ordered by elevation.
fn ring_gaps(
    cloud: &PointCloud,
    rings: &[u16],
    origins: &ReturnOrigins,
    up: DVec3,
) -> Result<BTreeMap<u16, f64>, FidelityError> {
    let mut elevations: BTreeMap<u16, Vec<f64>> = BTreeMap::new();
    for (i, (&point, &ring)) in cloud.positions.iter().zip(rings).enumerate() {
        if let Some(direction) = (point - origins.of(i)).try_normalize() {
            elevations.entry(ring).or_default().push(direction.dot(up).clamp(-1.0, 1.0).asin());
        }
    }
    let mut by_elevation: Vec<(u16, f64)> =
        elevations.into_iter().map(|(ring, mut values)| (ring, median(&mut values))).collect();
    if by_elevation.len() < 2 {
        return Err(FidelityError::TooFewRings(by_elevation.len()));
    }
    by_elevation.sort_by(|a, b| a.1.total_cmp(&b.1));
    let gap = |i: usize, j: usize| (by_elevation[j].1 - by_elevation[i].1).abs();
    let last = by_elevation.len() - 1;
    Ok((0..=last)
        .map(|i| {
            let below = if i > 0 { gap(i - 1, i) } else { 0.0 };
            let above = if i < last { gap(i, i + 1) } else { 0.0 };
            (by_elevation[i].0, below.max(above))
        })
        .collect())
}

fn median(values: &mut [f64]) -> f64 {
    let middle = values.len() / 2;
    *values.select_nth_unstable_by(middle, f64::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;
    use pointray_kernels::PatchHot;

    /// Two rings 10° apart seen from the origin, at ranges 10 and 20, and one patch on each,
    /// facing the sensor, of radius 2 beam spacings on the first and 1 on the second.
    fn two_rings() -> (PointCloud, PatchSet) {
        let at = |elevation: f64, range: f64, azimuth: f64| {
            let (e, a) = (elevation.to_radians(), azimuth.to_radians());
            DVec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin()) * range
        };
        let mut cloud = PointCloud::from_positions(vec![
            at(0.0, 10.0, 0.0),
            at(0.0, 10.0, 5.0),
            at(-10.0, 20.0, 0.0),
            at(-10.0, 20.0, 5.0),
        ]);
        cloud.rings = Some(vec![7, 7, 3, 3]);
        cloud.sensor_position = Some(DVec3::ZERO);
        let gap = 10f64.to_radians();
        let patch = |point: DVec3, radius: f64| {
            let facing = -point.normalize().as_vec3();
            PatchHot::isotropic(
                point.as_vec3(),
                facing.any_orthonormal_vector(),
                facing,
                [0.0; 6],
                radius as f32,
            )
        };
        let hot = vec![patch(cloud.positions[0], 2.0 * gap * 10.0), patch(cloud.positions[3], gap * 20.0)];
        (cloud, PatchSet { hot: hot.into(), ..PatchSet::default() })
    }

    #[test]
    fn ratios_are_radius_over_ring_gap_times_range() {
        let (cloud, patches) = two_rings();
        let origins = ReturnOrigins::of_cloud(&cloud, None).unwrap();
        let report = support_against_beam_spacing(&cloud, &patches, &[0, 3], &origins, Vec3::Z).unwrap();
        assert_eq!((report.patches, report.rings), (2, 2));
        assert!((report.max_ratio - 2.0).abs() < 1e-4, "{report:?}");
        assert!((report.p99_ratio - 2.0).abs() < 1e-4, "{report:?}");
        assert_eq!(report.over_limit_fraction, 0.0);
    }

    #[test]
    fn a_patch_seen_at_a_grazing_angle_is_measured_against_the_spacing_on_its_surface() {
        let (cloud, patches) = two_rings();
        // The second patch laid flat (normal up), seen 10° below the horizon: the rings lie
        // 1 / sin(10°) times farther apart on it than across the beam.
        let seen = &patches.hot[1];
        let flat = PatchHot::isotropic(seen.origin(), Vec3::X, Vec3::Z, [0.0; 6], seen.radius());
        let patches = PatchSet { hot: vec![flat].into(), ..PatchSet::default() };
        let origins = ReturnOrigins::of_cloud(&cloud, None).unwrap();
        let report = support_against_beam_spacing(&cloud, &patches, &[3], &origins, Vec3::Z).unwrap();
        let expected = 10f64.to_radians().sin();
        assert!((report.max_ratio - expected).abs() < 1e-3, "{report:?}");
    }

    #[test]
    fn clouds_without_rings_or_with_mismatched_sources_are_errors() {
        let (mut cloud, patches) = two_rings();
        let origins = ReturnOrigins::Fixed(DVec3::ZERO);
        let miscounted = support_against_beam_spacing(&cloud, &patches, &[0], &origins, Vec3::Z);
        assert!(matches!(miscounted, Err(FidelityError::PatchSourceCount { sources: 1, patches: 2 })));
        let past = support_against_beam_spacing(&cloud, &patches, &[0, 9], &origins, Vec3::Z);
        assert!(matches!(past, Err(FidelityError::PatchSourceOutOfRange { source_index: 9, .. })));
        cloud.rings = Some(vec![1; 4]);
        let one_ring = support_against_beam_spacing(&cloud, &patches, &[0, 3], &origins, Vec3::Z);
        assert!(matches!(one_ring, Err(FidelityError::TooFewRings(1))));
        cloud.rings = None;
        let none = support_against_beam_spacing(&cloud, &patches, &[0, 3], &origins, Vec3::Z);
        assert!(matches!(none, Err(FidelityError::NoRings)));
    }
}
