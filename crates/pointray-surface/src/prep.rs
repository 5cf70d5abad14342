//! `prep`: from a point cloud to a `PatchSet` (METHOD.md §2), stage by stage.

use std::borrow::Cow;

use glam::{DVec3, Vec2, Vec3};
use pointray_io::{MemoryBudget, PointCloud};
use pointray_kernels::interpolate_color::COLOR_SUPPORT_SCALE;
use pointray_kernels::tangent_frame::normal_basis;
use pointray_kernels::{Aabb, COLOR_NEIGHBORS, PackedTangentFrame, PatchCold, PatchHot, TangentFrame};
use pointray_patches::patch_bounds::patch_box;
use pointray_patches::prep_settings::MIN_NEIGHBOURS;
use pointray_patches::{OutlierFilter, PatchSet, PrepSettings, RadiusMode};
use rayon::prelude::*;

use crate::cold_records::{cold_records, color_neighbor_table};
use crate::density_radius::{RadiusAdjustments, adaptive_radii, cell_radii};
use crate::duplicates::{largest_merge_distance, merge_duplicates};
use crate::input_validation::{
    validate_intensities, validate_part, validate_positions, validate_settings, validate_size,
};
use crate::morton::morton_order;
use crate::neighbors::{Neighbors, k_nearest};
use crate::normals::pca_normals;
use crate::orientation::{orient_consistently, orient_toward};
use crate::outlier_removal::inliers;
use crate::prep_error::PrepError;
use crate::prep_progress::{PrepProgress, Stage};
use crate::prep_report::{FitCounts, PrepReport, RadiusFallbacks};
use crate::quadratic_fit::{FitKind, PatchFit, fit_patch};
use crate::scan::prep::{scan_shaped, scan_structure};
use crate::shaped_patches::{ShapedPatches, count_fits};
use crate::stage_clock::StageClock;
use crate::support_radius::{RadiusSource, support_radius};
use crate::trimmed_centre::trimmed_centre;

/// The Wendland scale `h_i` is this multiple of the farthest neighbour's distance, so
/// that every neighbour keeps some weight (METHOD.md §2.6, ours).
const WENDLAND_SCALE: f32 = 1.1;

/// Points per progress report in the per-point stages.
const PROGRESS_CHUNK: usize = 16_384;

/// Changes whenever `prep` makes different patches from the same input and settings (the
/// cell margin went from 1.15 to 1.5 in revision 2; revision 3 brought scan-aware patches
/// and the packed record; in revision 4 orientation joins blocks, which can turn a different
/// set of normals; in revision 5 a scan's patches follow the levels of steps, stand on their
/// faces and are cut back on one side; in revision 6 a scan's planes favour the returns near
/// the point, and a patch stops short of a line beside it that saw nothing; in revision 7 the
/// gap to the next line leaves out returns that the range noise may have moved across it; in
/// revision 8 a scan's planes take normals smoothed over their neighbours'; in revision 9
/// the hot record is 32 bytes, its frame and `c0` packed anew; in revision 10 equally distant
/// neighbours come in index order; in revision 11 raw sweeps arrive with their scan lines and
/// laser origins; in revision 12 the store holds the compact record, so a cache entry decodes
/// to quantised positions and radii; in revision 13 a ray passing a scan's patch cuts its edge
/// back to part of the way to the ray, not to the ray, and a cloud is recentred on its
/// trimmed centre, not its box's; in revision 14 a scan's plane seen obliquely stretches its patch
/// only where its neighbours' planes agree), so that caches keyed on the settings also key on this and
/// never serve patches of an older rule.
pub const PREP_REVISION: u32 = 14;

/// Turns `cloud` into one patch per distinct point, in Morton order.
pub fn prep(
    cloud: &PointCloud,
    settings: &PrepSettings,
    progress: &dyn PrepProgress,
) -> Result<(PatchSet, PrepReport), PrepError> {
    prep_cloud(Cow::Borrowed(cloud), settings, progress)
}

/// As `prep`, taking the cloud so that its f64 positions (24 bytes a point) are freed as
/// soon as the recentred f32 copy exists: the way to prep the largest clouds.
pub fn prep_owned(
    cloud: PointCloud,
    settings: &PrepSettings,
    progress: &dyn PrepProgress,
) -> Result<(PatchSet, PrepReport), PrepError> {
    prep_cloud(Cow::Owned(cloud), settings, progress)
}

/// As `prep`, for a tile of a larger cloud (`tiles::tiled_prep`): recentred on the whole cloud's
/// offset, so that the tile's patches are the ones a single pass over the whole cloud makes.
pub fn prep_in_context(
    cloud: &PointCloud,
    settings: &PrepSettings,
    context: &TileContext,
    progress: &dyn PrepProgress,
) -> Result<(PatchSet, PrepReport), PrepError> {
    prep_with_context(Cow::Borrowed(cloud), settings, Some(context), progress)
}

/// What a tile of a cloud takes from the whole cloud.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TileContext {
    /// The recentring offset: `input = local + offset`.
    pub offset: DVec3,
    /// The farthest apart (local units) two points of the cloud may lie and merge as
    /// duplicates: a bound for halos. Whether a pair merges follows from its own coordinates
    /// (`duplicates::merge_as_duplicates`).
    pub duplicate_distance: f32,
    /// The whole cloud's box (input units) and its points, for the checks a tile makes.
    pub bounds: (DVec3, DVec3),
    pub points: usize,
}

fn prep_cloud(
    cloud: Cow<'_, PointCloud>,
    settings: &PrepSettings,
    progress: &dyn PrepProgress,
) -> Result<(PatchSet, PrepReport), PrepError> {
    let settings = neighbourhoods_within(settings, cloud.len());
    prep_with_context(cloud, &settings, None, progress)
}

/// `settings` with `k` and `normal_k` cut to the other points of a cloud of `points` (the
/// PCL and pypcd4 test clouds hold 8), but never below `MIN_NEIGHBOURS`, the fewest a normal
/// needs: a small cloud preps with the neighbours it has, with a warning, instead of being
/// refused.
fn neighbourhoods_within(settings: &PrepSettings, points: usize) -> PrepSettings {
    let others = u32::try_from(points.saturating_sub(1)).unwrap_or(u32::MAX).max(MIN_NEIGHBOURS);
    if settings.k.max(settings.normal_k) <= others {
        return *settings;
    }
    // A cloud too small even for that is refused next, saying so; a warning would miscount.
    if points > MIN_NEIGHBOURS as usize {
        warn_of_smaller_neighbourhoods(settings, points, others);
    }
    PrepSettings { k: settings.k.min(others), normal_k: settings.normal_k.min(others), ..*settings }
}

fn warn_of_smaller_neighbourhoods(settings: &PrepSettings, points: usize, others: u32) {
    tracing::warn!(
        "{points} points: each has {others} neighbours at most, so k = {} and normal_k = {} become {} and {}",
        settings.k,
        settings.normal_k,
        settings.k.min(others),
        settings.normal_k.min(others)
    );
}

/// Each array is dropped as soon as its last stage is done, so that the peak (in the
/// support radii and the fit) holds little more than the neighbour table, the frames and
/// the patches.
fn prep_with_context(
    mut cloud: Cow<'_, PointCloud>,
    settings: &PrepSettings,
    context: Option<&TileContext>,
    progress: &dyn PrepProgress,
) -> Result<(PatchSet, PrepReport), PrepError> {
    let (k, normal_k) = (settings.k as usize, settings.normal_k as usize);
    let mut clock = StageClock { progress, times: Vec::new() };
    let count = cloud.len();
    clock.run(Stage::Validate, count, || validate(&cloud, settings, context))?;
    let (offset, recentred) = clock.run(Stage::Recentre, count, || match context {
        Some(context) => (context.offset, recentre_on(&cloud.positions, context.offset)),
        None => recentre(&cloud.positions),
    });
    // Only the attributes are read from here on (gathered through `source`).
    if let Cow::Owned(owned) = &mut cloud {
        owned.positions = Vec::new();
    }
    let cloud = &*cloud;
    let order = clock.run(Stage::MortonSort, count, || morton_order(&recentred));
    let sorted = gather(&recentred, &order);
    drop(recentred);
    // Each pair's tolerance follows from its own coordinates in the shared frame, so that a
    // tile merges what a single pass over the whole cloud merges.
    let merge =
        clock.run(Stage::MergeDuplicates, count, || merge_duplicates(&sorted, settings.duplicate_tolerance));
    if merge.kept.len() < k + 1 {
        return Err(PrepError::TooFewDistinctPoints { found: merge.kept.len(), k });
    }
    let (distinct, merged_duplicates) = (merge.kept.len(), merge.merged_count);
    let kept = match &settings.remove_outliers {
        Some(filter) => clock
            .run(Stage::OutlierRemoval, merge.kept.len(), || keep_inliers(filter, &sorted, &merge.kept, k))?,
        None => merge.kept,
    };
    let removed_outliers = distinct - kept.len();
    // `source[i]` is the input index of patch `i`: every per-point attribute is gathered
    // through it once.
    let source = gather(&order, &kept);
    drop(order);
    let points = gather(&sorted, &kept);
    drop((sorted, kept));
    let patches = points.len();
    let mut neighbors = clock.run(Stage::Neighbours, patches, || k_nearest(&points, k.max(normal_k)));
    let scan =
        clock.run(Stage::ScanLines, patches, || scan_structure(&points, cloud, &source, settings, offset));
    let colors = has_point_colors(cloud);
    // Past the shaping only the colour table reads the neighbours; the scan route never
    // reads them, and the unstructured route narrows them before its fit's peak.
    let kept_neighbors = color_table_width(colors, k);
    let unstructured_because = scan.as_ref().and_then(|found| found.as_ref().err().copied());
    let shaped = match scan.and_then(Result::ok) {
        Some(scan) => {
            neighbors.narrow(kept_neighbors);
            scan_shaped(&points, scan, settings.disk_scale, &mut clock)
        }
        None => {
            let input = UnstructuredInput { cloud, source: &source, settings, offset, kept_neighbors };
            unstructured_shaped(&points, &mut neighbors, &input, &mut clock)
        }
    };
    drop(points);
    let hot = shaped.hot;
    let (cold, color_neighbors) = clock.run(Stage::ColdRecords, patches, || {
        (gather_cold(cloud, &source, &shaped.color_radii), color_neighbor_table(neighbors, colors))
    });
    let aabbs: Vec<Aabb> =
        clock.run(Stage::Boxes, patches, || hot.par_iter().map(|h| patch_box(h, settings.boxes)).collect());
    let report = PrepReport {
        input_points: count,
        merged_duplicates,
        removed_outliers,
        patches,
        replaced_input_normals: shaped.replaced_input_normals,
        fits: shaped.fits,
        radius_fallbacks: shaped.radius_fallbacks,
        radius_adjustments: shaped.radius_adjustments,
        scan: shaped.scan,
        unstructured_because,
        offset,
        patch_sources: source,
        stage_times: clock.times,
    };
    let patches = PatchSet {
        settings: *settings,
        offset,
        aabbs: aabbs.into(),
        hot: hot.into(),
        cold: cold.into(),
        color_neighbors: color_neighbors.into(),
        coarse: None,
    };
    Ok((patches, report))
}

/// Patches of unstructured points: PCA normals oriented over the neighbour graph or toward a
/// sensor, round supports of the chosen radius mode, and quadratic fits (METHOD.md §2).
fn unstructured_shaped(
    points: &[Vec3],
    neighbors: &mut Neighbors,
    input: &UnstructuredInput,
    clock: &mut StageClock,
) -> ShapedPatches {
    let UnstructuredInput { cloud, source, settings, offset, kept_neighbors } = *input;
    let (k, patches) = (settings.k as usize, points.len());
    let (mut normals, replaced_input_normals) =
        clock.run(Stage::Normals, patches, || normals_for(points, neighbors, cloud, source, settings));
    clock.run(Stage::Orientation, patches, || {
        orient(points, &mut normals, neighbors, cloud, settings, offset)
    });
    let (tangent_frames, frames) = clock.run(Stage::Frames, patches, || stored_frames(&normals));
    let radii = clock.run(Stage::SupportRadii, patches, || {
        support_radii(points, &normals, &frames, neighbors, k, settings.radius)
    });
    drop(normals); // the frames hold them
    // The fit reads only k neighbours: the rest of the table is freed before its peak.
    neighbors.narrow(kept_neighbors);
    let progress = clock.progress;
    let (hot, fits) = clock.run(Stage::QuadraticFit, patches, || {
        fit_patches(
            points,
            (&tangent_frames, &frames),
            &radii.chosen,
            neighbors,
            k,
            settings.disk_scale,
            progress,
        )
    });
    ShapedPatches {
        hot,
        fits,
        color_radii: radii.paper,
        radius_fallbacks: radii.fallbacks,
        radius_adjustments: radii.adjustments,
        replaced_input_normals,
        scan: None,
    }
}

/// What the unstructured route reads besides the points and their neighbours.
#[derive(Clone, Copy)]
struct UnstructuredInput<'a> {
    cloud: &'a PointCloud,
    /// The input index of each point.
    source: &'a [u32],
    settings: &'a PrepSettings,
    offset: DVec3,
    /// Neighbours per point kept past the support radii (`color_table_width`).
    kept_neighbors: usize,
}

/// The neighbours kept past the fit: `k` for the fit, and the colour table's width when the
/// points carry colours.
fn color_table_width(colors: bool, k: usize) -> usize {
    if colors { k.max(COLOR_NEIGHBORS) } else { k }
}

fn validate(
    cloud: &PointCloud,
    settings: &PrepSettings,
    context: Option<&TileContext>,
) -> Result<(), PrepError> {
    validate_settings(settings)?;
    validate_size(
        cloud.len(),
        settings,
        cloud.attribute_bytes_per_point(),
        &MemoryBudget::of_this_machine(),
    )?;
    let expected = cloud.len();
    let lengths = [
        ("normals", cloud.normals.as_ref().map(Vec::len)),
        ("colours", cloud.colors.as_ref().map(Vec::len)),
        ("intensities", cloud.intensities.as_ref().map(Vec::len)),
    ];
    for (attribute, found) in lengths {
        if let Some(found) = found.filter(|&found| found != expected) {
            return Err(PrepError::AttributeLength { attribute, found, expected });
        }
    }
    validate_intensities(cloud.intensities.as_deref())?;
    let k = settings.k as usize;
    match context {
        Some(context) => validate_part(&cloud.positions, k, (context.bounds, context.points)),
        None => validate_positions(&cloud.positions, k),
    }
}

/// Recentres on the trimmed centre in f64, then drops to f32: geo-referenced coordinates
/// (~10^6) would otherwise lose their centimetres.
pub(crate) fn recentre(positions: &[DVec3]) -> (DVec3, Vec<Vec3>) {
    let centre = trimmed_centre(positions);
    (centre, recentre_on(positions, centre))
}

/// The box of `positions` (min, max).
pub(crate) fn bounds_of(positions: &[DVec3]) -> (DVec3, DVec3) {
    positions
        .par_iter()
        .fold(|| (DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)))
        .reduce(|| (DVec3::INFINITY, DVec3::NEG_INFINITY), |(a, b), (c, d)| (a.min(c), b.max(d)))
}

pub(crate) fn recentre_on(positions: &[DVec3], centre: DVec3) -> Vec<Vec3> {
    positions.par_iter().map(|&p| (p - centre).as_vec3()).collect()
}

/// The farthest apart two of `points` can lie and still merge as duplicates: a bound for
/// halos, taken at the frame's largest coordinate.
pub(crate) fn largest_duplicate_distance(settings: &PrepSettings, points: &[Vec3]) -> f32 {
    let magnitude = points.par_iter().map(|p| p.abs().max_element()).reduce(|| 0.0, f32::max);
    largest_merge_distance(magnitude, settings.duplicate_tolerance)
}

/// The input's normals (normalised) unless asked to recompute or absent, else PCA
/// normals. Input normals that cannot be normalised are replaced by PCA normals, turned
/// to agree with their neighbours' input normals; their count is returned.
fn normals_for(
    points: &[Vec3],
    neighbors: &Neighbors,
    cloud: &PointCloud,
    source: &[u32],
    settings: &PrepSettings,
) -> (Vec<Vec3>, usize) {
    let normal_k = settings.normal_k as usize;
    let input = cloud.normals.as_ref().filter(|_| !settings.recompute_normals);
    let Some(input) = input else {
        return (pca_normals(points, neighbors, normal_k), 0);
    };
    let mut normals: Vec<Vec3> =
        source.par_iter().map(|&i| input[i as usize].try_normalize().unwrap_or(Vec3::ZERO)).collect();
    let broken: Vec<usize> = (0..normals.len()).filter(|&i| normals[i] == Vec3::ZERO).collect();
    if !broken.is_empty() {
        let pca = pca_normals(points, neighbors, normal_k);
        for &i in &broken {
            let around: Vec3 = neighbors.of(i).iter().map(|&j| normals[j as usize]).sum();
            normals[i] = if pca[i].dot(around) < 0.0 { -pca[i] } else { pca[i] };
        }
    }
    (normals, broken.len())
}

/// Toward the sensor when one is known; else, for computed normals, consistently over
/// the neighbour graph. Input normals are taken as already oriented.
fn orient(
    points: &[Vec3],
    normals: &mut [Vec3],
    neighbors: &Neighbors,
    cloud: &PointCloud,
    settings: &PrepSettings,
    offset: DVec3,
) {
    if let Some(sensor) = settings.sensor.or(cloud.sensor_position) {
        orient_toward(points, normals, (sensor - offset).as_vec3());
    } else if settings.recompute_normals || cloud.normals.is_none() {
        orient_consistently(points, normals, neighbors);
    }
}

/// The statistical outlier filter over the merged points `kept` (indices into `sorted`);
/// an error when too few points would remain for `k` neighbours.
fn keep_inliers(
    filter: &OutlierFilter,
    sorted: &[Vec3],
    kept: &[u32],
    k: usize,
) -> Result<Vec<u32>, PrepError> {
    let inliers = inliers(filter, &gather(sorted, kept));
    let survivors: Vec<u32> =
        kept.iter().zip(inliers).filter(|(_, inlier)| *inlier).map(|(&i, _)| i).collect();
    if survivors.len() < k + 1 {
        return Err(PrepError::TooFewDistinctPoints { found: survivors.len(), k });
    }
    Ok(survivors)
}

/// Each patch's support radius, and the paper's radius it was derived from, which also sets
/// how far the point's colour reaches (`PatchCold::color_reach`).
struct SupportRadii {
    chosen: Vec<f32>,
    paper: Vec<f32>,
    fallbacks: RadiusFallbacks,
    adjustments: RadiusAdjustments,
}

/// The paper's radii (METHOD.md §2.3), then, in adaptive or cell mode, their correction.
fn support_radii(
    points: &[Vec3],
    normals: &[Vec3],
    frames: &[TangentFrame],
    neighbors: &Neighbors,
    k: usize,
    mode: RadiusMode,
) -> SupportRadii {
    let (paper, fallbacks) = paper_radii(points, normals, neighbors, k);
    let (chosen, adjustments) = match mode {
        RadiusMode::Paper => (paper.clone(), RadiusAdjustments::default()),
        RadiusMode::Adaptive => adaptive_radii(frames, points, neighbors, k, &paper),
        RadiusMode::Cell => (cell_radii(frames, points, neighbors, k, &paper), RadiusAdjustments::default()),
    };
    SupportRadii { chosen, paper, fallbacks, adjustments }
}

fn paper_radii(
    points: &[Vec3],
    normals: &[Vec3],
    neighbors: &Neighbors,
    k: usize,
) -> (Vec<f32>, RadiusFallbacks) {
    let spacing_sum: f64 =
        (0..points.len()).into_par_iter().map(|i| f64::from(neighbors.distances_of(i)[0])).sum();
    let mean_spacing = (spacing_sum / points.len() as f64) as f32;
    let (radii, sources): (Vec<f32>, Vec<RadiusSource>) = (0..points.len())
        .into_par_iter()
        .map(|i| {
            let farthest = points[neighbors.of(i)[k - 1] as usize];
            support_radius(points[i], normals[i], farthest, mean_spacing)
        })
        .unzip();
    let count = |wanted| sources.par_iter().filter(|&&s| s == wanted).count();
    (
        radii,
        RadiusFallbacks { distance: count(RadiusSource::Distance), spacing: count(RadiusSource::Spacing) },
    )
}

/// Each patch's frame as stored, and what it decodes to: the frame the fit works in.
fn stored_frames(normals: &[Vec3]) -> (Vec<PackedTangentFrame>, Vec<TangentFrame>) {
    normals
        .par_iter()
        .map(|&n| {
            let packed = PackedTangentFrame::new(n, normal_basis(n).0);
            (packed, packed.decode())
        })
        .unzip()
}

fn fit_patches(
    points: &[Vec3],
    (tangent_frames, frames): (&[PackedTangentFrame], &[TangentFrame]),
    radii: &[f32],
    neighbors: &Neighbors,
    k: usize,
    disk_scale: f32,
    progress: &dyn PrepProgress,
) -> (Vec<PatchHot>, FitCounts) {
    let (hot, kinds): (Vec<PatchHot>, Vec<FitKind>) = (0..points.len())
        .into_par_iter()
        .with_min_len(PROGRESS_CHUNK)
        .map(|i| {
            if i % PROGRESS_CHUNK == 0 {
                progress.advanced(PROGRESS_CHUNK.min(points.len() - i) as u64);
            }
            let fit = fit_one(points, &frames[i], radii[i], neighbors, k, i);
            let support = Vec2::splat(radii[i] * disk_scale);
            (PatchHot::new(points[i], tangent_frames[i], support, fit.coefficients), fit.kind)
        })
        .unzip();
    (hot, count_fits(&kinds))
}

/// The patch of point `i` from the point itself and its `k` nearest neighbours.
fn fit_one(
    points: &[Vec3],
    frame: &TangentFrame,
    radius: f32,
    neighbors: &Neighbors,
    k: usize,
    i: usize,
) -> PatchFit {
    let origin = points[i];
    let indices = &neighbors.of(i)[..k];
    let distances = &neighbors.distances_of(i)[..k];
    let samples =
        indices.iter().zip(distances).map(|(&j, &r)| (frame.to_local(points[j as usize] - origin), r));
    let h = WENDLAND_SCALE * distances[k - 1];
    fit_patch(std::iter::once((Vec3::ZERO, 0.0)).chain(samples), h, radius)
}

/// Whether the points carry a colour to blend: their own, or one that a material's
/// intensity ramp makes at load.
fn has_point_colors(cloud: &PointCloud) -> bool {
    cloud.colors.is_some() || cloud.intensities.is_some()
}

fn gather_cold(cloud: &PointCloud, source: &[u32], paper_radii: &[f32]) -> Vec<PatchCold> {
    let colors = cloud.colors.as_deref().map(|values| gather(values, source));
    let intensities = cloud.intensities.as_deref().map(|values| gather(values, source));
    let mut cold = cold_records(colors.as_deref(), intensities.as_deref(), source.len());
    for (record, radius) in cold.iter_mut().zip(paper_radii) {
        record.color_reach = COLOR_SUPPORT_SCALE * radius;
    }
    cold
}

/// `values[i]` for each `i` of `source`, on every core.
pub(crate) fn gather<T: Copy + Send + Sync>(values: &[T], source: &[u32]) -> Vec<T> {
    source.par_iter().map(|&i| values[i as usize]).collect()
}
