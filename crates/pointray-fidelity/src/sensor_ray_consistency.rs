//! Sensor-ray consistency, a measure with no ground truth: the sensor saw each return first
//! along its ray, so the surface made from the returns should first be met there too. A
//! surface met well before the return floats in front of what the sensor saw; one met well
//! after it, or not at all, has a hole where the sensor saw something.

use std::sync::Arc;
use std::time::Instant;

use glam::{Affine3A, DVec3, Vec3};
use pointray_cpu::CpuRenderer;
use pointray_io::PointCloud;
use pointray_kernels::Ray;
use pointray_patches::PatchSet;
use pointray_scene::{Background, Camera, Geometry, Material, PatchAcceptance, Scene, SceneObject};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::consistency_report::{ConsistencyCounts, ConsistencyReport};
use crate::local_spacing::nth_neighbor_distances;
use crate::range_tolerance::{RangeTolerance, SPACING_NEIGHBOR};
use crate::sensor_pixel_consistency::sensor_pixel_consistency;
use crate::{FidelityError, ReturnOrigins};

#[derive(Clone, Debug, PartialEq)]
pub struct ConsistencyOptions {
    /// At most this many returns are checked, drawn at random from a larger cloud.
    pub rays: usize,
    /// Seeds the draw, so that a run can be repeated.
    pub seed: u64,
    pub tolerance: RangeTolerance,
    pub acceptance: PatchAcceptance,
    /// Every return's sensor, overriding what the file says.
    pub sensor: Option<DVec3>,
}

impl Default for ConsistencyOptions {
    fn default() -> Self {
        Self {
            rays: 200_000,
            seed: 0,
            tolerance: RangeTolerance::default(),
            acceptance: PatchAcceptance::Disk,
            sensor: None,
        }
    }
}

/// What one return's ray met.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayOutcome {
    /// The first hit lies within the tolerance of the return.
    Consistent,
    /// The first hit lies more than the tolerance before the return, but on the return's own
    /// surface: within the tolerance of the return along the surface's normal. A ray that
    /// grazes the road at 5° meets it 23 cm early for 2 cm of height; that is no floater.
    MetOwnSurfaceEarly,
    /// The first hit lies more than the tolerance before the return, off its surface: a
    /// floater.
    OccludedInFront,
    /// The first hit lies more than the tolerance beyond the return (`missed: false`), or
    /// there is none: a hole.
    PassedThrough { missed: bool },
}

/// Where a ray first met the surface: its parameter, and the return's distance from the
/// surface's tangent plane there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FirstHit {
    pub t: f64,
    pub return_off_surface: f64,
}

impl RayOutcome {
    /// The outcome of a ray whose first hit is `hit` (`None`: no hit) toward a return at
    /// `range`, with `tolerance`.
    pub fn classify(hit: Option<FirstHit>, range: f64, tolerance: f64) -> Self {
        match hit {
            None => RayOutcome::PassedThrough { missed: true },
            Some(hit) if (hit.t - range).abs() <= tolerance => RayOutcome::Consistent,
            Some(hit) if hit.t < range && hit.return_off_surface <= tolerance => {
                RayOutcome::MetOwnSurfaceEarly
            }
            Some(hit) if hit.t < range => RayOutcome::OccludedInFront,
            Some(_) => RayOutcome::PassedThrough { missed: false },
        }
    }

    pub fn is_consistent(self) -> bool {
        matches!(self, RayOutcome::Consistent | RayOutcome::MetOwnSurfaceEarly)
    }
}

/// Casts the ray of up to `options.rays` returns of `cloud` from their sensor against
/// `patches` (prepped from `cloud`) with the CPU renderer, and counts the outcomes.
pub fn sensor_ray_consistency(
    cloud: &PointCloud,
    patches: Arc<PatchSet>,
    options: &ConsistencyOptions,
) -> Result<ConsistencyReport, FidelityError> {
    options.tolerance.validate()?;
    if options.rays == 0 {
        return Err(FidelityError::NoRays);
    }
    if patches.is_empty() {
        return Err(FidelityError::EmptyPatchSet);
    }
    let started = Instant::now();
    let origins = ReturnOrigins::of_cloud(cloud, options.sensor)?;
    let offset = patches.offset;
    let local: Vec<Vec3> = cloud.positions.iter().map(|&p| (p - offset).as_vec3()).collect();
    let chosen = draw_returns(cloud.len(), options.rays, options.seed);
    let spacings = nth_neighbor_distances(&local, &chosen, SPACING_NEIGHBOR)?;
    let renderer = CpuRenderer::new(&patches_scene(patches.clone()));
    let checked: Vec<Option<(RayOutcome, f64)>> = chosen
        .par_iter()
        .zip(&spacings)
        .map(|(&i, &spacing)| {
            let sensor = origins.of(i) - offset;
            let to_return = local[i].as_dvec3() - sensor;
            let range = to_return.length();
            let direction = (to_return / range).as_vec3();
            (range > 0.0 && direction.is_finite()).then(|| {
                let tolerance = options.tolerance.at(range, f64::from(spacing));
                let ray = Ray::new(sensor.as_vec3(), direction);
                let hit = renderer.first_hit(&ray, 0.0, f32::INFINITY, options.acceptance).map(|hit| {
                    let t = f64::from(hit.t);
                    let off = (to_return - direction.as_dvec3() * t).dot(hit.normal.as_dvec3()).abs();
                    FirstHit { t, return_off_surface: off }
                });
                (RayOutcome::classify(hit, range, tolerance), tolerance)
            })
        })
        .collect();
    let counts = ConsistencyCounts::of(&checked);
    let sensor_of = |i: usize| origins.of(i) - offset;
    let pixels = sensor_pixel_consistency(&renderer, &local, sensor_of, &chosen, options.acceptance);
    let seconds = started.elapsed().as_secs_f64();
    Ok(ConsistencyReport::new(cloud.len(), &patches, options, counts, pixels, seconds))
}

/// `budget` return indices drawn at random without repeats, in increasing order; every
/// index when there are no more than that.
fn draw_returns(count: usize, budget: usize, seed: u64) -> Vec<usize> {
    if count <= budget {
        return (0..count).collect();
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut chosen = rand::seq::index::sample(&mut rng, count, budget).into_vec();
    chosen.sort_unstable();
    chosen
}

/// The patches alone, in their own recentred coordinates: geo-referenced scans keep their
/// precision, and rays are moved there instead.
fn patches_scene(patches: Arc<PatchSet>) -> Scene {
    let object = SceneObject {
        name: "points".to_owned(),
        transform: Affine3A::IDENTITY,
        material: Material::default(),
        geometry: Geometry::Patches(patches),
    };
    let camera = Camera { position: Vec3::Z, look_at: Vec3::ZERO, up: Vec3::Y, vertical_fov_degrees: 40.0 };
    Scene { camera, lights: Vec::new(), background: Background::Solid(Vec3::ZERO), objects: vec![object] }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outcomes_split_at_the_tolerance_on_either_side() {
        let off_surface = |t: f64| Some(FirstHit { t, return_off_surface: 10.0 - t });
        assert_eq!(RayOutcome::classify(off_surface(10.05), 10.0, 0.1), RayOutcome::Consistent);
        assert_eq!(RayOutcome::classify(off_surface(9.95), 10.0, 0.1), RayOutcome::Consistent);
        assert_eq!(RayOutcome::classify(off_surface(9.5), 10.0, 0.1), RayOutcome::OccludedInFront);
        let late = RayOutcome::classify(off_surface(11.0), 10.0, 0.1);
        assert_eq!(late, RayOutcome::PassedThrough { missed: false });
        assert_eq!(RayOutcome::classify(None, 10.0, 0.1), RayOutcome::PassedThrough { missed: true });
    }

    #[test]
    fn an_early_hit_on_the_return_s_own_surface_is_consistent_and_counted_apart() {
        let grazing = Some(FirstHit { t: 9.0, return_off_surface: 0.03 });
        assert_eq!(RayOutcome::classify(grazing, 10.0, 0.1), RayOutcome::MetOwnSurfaceEarly);
        assert!(RayOutcome::MetOwnSurfaceEarly.is_consistent());
        // Beyond the return, off-surface distance does not excuse a hole.
        let late = Some(FirstHit { t: 11.0, return_off_surface: 0.03 });
        assert_eq!(RayOutcome::classify(late, 10.0, 0.1), RayOutcome::PassedThrough { missed: false });
    }

    #[test]
    fn draws_are_distinct_sorted_repeatable_and_all_when_few() {
        let drawn = draw_returns(1000, 100, 7);
        assert_eq!(drawn.len(), 100);
        assert!(drawn.windows(2).all(|pair| pair[0] < pair[1]));
        assert_eq!(drawn, draw_returns(1000, 100, 7));
        assert_ne!(drawn, draw_returns(1000, 100, 8));
        assert_eq!(draw_returns(5, 100, 7), vec![0, 1, 2, 3, 4]);
    }
}
