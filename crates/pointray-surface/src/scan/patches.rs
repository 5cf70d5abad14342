//! Patches of a LiDAR scan (`ScanLines`): elliptical supports that reach halfway to the next
//! return along the scan line and halfway to the next line, fitted to neighbourhoods that span
//! lines (where a step lies among them, to the level the point lies on: `scan::levels`); on a
//! step's face, which one line alone sees, a patch over the face; small disks facing the
//! sensor where the neighbours agree on no surface.

use glam::{Vec2, Vec3};
use pointray_kernels::tangent_frame::normal_basis;
use pointray_kernels::{PackedTangentFrame, TangentFrame};
use rayon::prelude::*;

use crate::quadratic_fit::{FitKind, PatchFit};
use crate::scan::edges::{Silhouette, silhouettes};
use crate::scan::free_space::Ellipse;
use crate::scan::levels::{LevelFit, StepFace, level_fit};
use crate::scan::lines::ScanLines;
use crate::scan::neighborhood::{
    MAX_RISE, ScanNeighborhood, agreeing_neighborhood, candidates, neighborhood_agreeing_with,
};
use crate::scan::normal_smoothing::smoothed_normal;

/// Each radius is this multiple of the spacing to the next return on its axis: half the
/// spacing meets the neighbour's patch, and the rest covers the corners of the cell between
/// four returns and the curvature of the surface between them.
const COVER: f32 = 1.0;

/// A spacing between returns is trusted up to this multiple of what the sensor's angular step
/// predicts for the surface's slope: beyond it the next return lies past a dropout or on
/// another object.
const PREDICTED_SPACING_TRUST: f32 = 2.0;

/// Grazing surfaces spread the beams' spacing by `1 / |cos(incidence)|`, bounded here (and
/// by `pointray-fidelity` where it measures supports against that spacing).
pub const MIN_INCIDENCE_COSINE: f32 = 0.05;

/// A plane that the sensor sees this nearly edge-on (|cos(incidence)| below it, about 1°)
/// is not a surface the returns show: returns down a pole or a wall's edge, with one more
/// along the line, span a plane through the sensor itself. A road 1.7 m below the sensor
/// stays above it out to 85 m.
const EDGE_ON_COSINE: f32 = 0.02;

/// A neighbourhood that spreads out of its plane by more than this multiple of the range noise
/// (`ScanNeighborhood::spread_over_noise`) is not one surface: a step or a crease lies in it,
/// and only the returns within the noise of a plane through the point count.
const MAX_SPREAD: f32 = 2.0;

/// A return on another line counts toward the gap between lines only when its offset across
/// them exceeds this many standard deviations of the range noise, projected on that axis:
/// within it, the noise could have put it on either side of the point.
const INTERLEAVE_SIGMAS: f32 = 2.0;

/// A footprint patch reaches this many angular steps from its return: 1/√2 would just meet
/// the cell's corners on a regular grid; more covers the jitter of real azimuths.
const FOOTPRINT_COVER: f32 = 0.75;

/// At an occluder's edge a patch reaches this fraction of the predicted spacing toward the
/// next ray, which saw the surface behind: the silhouette lies somewhere between the two rays,
/// and the patch of the return before it on the other side covers the gap to it.
const IN_FRONT_REACH: f32 = 0.5;

/// Beside an occluder, a patch reaches this multiple of the predicted spacing: with the next
/// line a spacing away on the other axis, an ellipse needs 1/cos 30° ≈ 1.15 of a step to
/// cover the corners of its cells up to the next ray, which met the occluder.
const BEHIND_REACH: f32 = 1.5;

/// A plane the sensor sees more obliquely than this (|cos(incidence)| below it, past about 75°)
/// stretches its patch across the lines to four footprints or more (`stretch_confirmed`).
const OBLIQUE_COSINE: f32 = 0.25;

/// An oblique plane's members confirm it where at least this share of their own planes lie
/// within `AGREEMENT_COSINE` (about 25°) of it: the range noise tilts the planes of close
/// returns by less.
const AGREEMENT_SHARE: f32 = 0.5;
const AGREEMENT_COSINE: f32 = 0.9;

/// A plane is level where its normal lies within about 18° of the spinning sensor's axis (+z),
/// which the scan lines take for up.
const LEVEL_COSINE: f32 = 0.95;

/// A scan patch before packing: its oriented normal, stored frame, radii `(d_u, d_v)` with
/// `d_u >= d_v`, and fit.
#[derive(Clone, Copy, Debug)]
pub struct ScanPatch {
    /// The centre of its support: the return itself, or beside it in its plane where the
    /// support was cut back on one side.
    pub centre: Vec3,
    pub normal: Vec3,
    pub frame: PackedTangentFrame,
    pub radii: Vec2,
    pub fit: PatchFit,
    /// Whether its neighbours agreed on a surface (else it is a small disk facing the sensor).
    pub on_surface: bool,
}

impl ScanPatch {
    /// A plane's patch over `ellipse`.
    fn over_surface(ellipse: Ellipse) -> Self {
        let frame = PackedTangentFrame::new(ellipse.normal, ellipse.major);
        let fit = PatchFit { coefficients: [0.0; 6], kind: FitKind::Plane };
        Self {
            centre: ellipse.centre,
            normal: ellipse.normal,
            frame,
            radii: ellipse.radii,
            fit,
            on_surface: true,
        }
    }
}

/// Every point's patch, in parallel: every neighbourhood's plane first, so that each patch can
/// take its normal smoothed over its neighbours' (`scan::normal_smoothing`). The neighbourhoods
/// are not kept, which would hold a few hundred bytes per return: each is found again from the
/// plane that chose its members and the normal fitted to them, without a second vote or fit.
pub fn scan_patches(points: &[Vec3], scan: &ScanLines) -> Vec<ScanPatch> {
    let (fitted_normals, choosers): (Vec<Vec3>, Vec<Vec3>) = (0..points.len())
        .into_par_iter()
        .with_min_len(1024)
        .map(|i| {
            let (neighborhood, chooser) = agreeing_neighborhood(points, scan, i, &candidates(scan, i));
            (neighborhood.normal, chooser)
        })
        .unzip();
    (0..points.len())
        .into_par_iter()
        .with_min_len(1024)
        .map(|i| scan_patch(points, scan, i, &fitted_normals, choosers[i]))
        .collect()
}

/// Point `i`'s patch. Its neighbourhood (found again from `chooser`, the plane that chose its
/// members) judges whether the neighbours lie on one surface; its normal smoothed over theirs
/// (`fitted_normals`) shapes the patch.
fn scan_patch(
    points: &[Vec3],
    scan: &ScanLines,
    i: usize,
    fitted_normals: &[Vec3],
    chooser: Vec3,
) -> ScanPatch {
    let toward_sensor = (scan.sensor[i] - points[i]).normalize_or(Vec3::Z);
    // The lines' angles span no distance at the sensor itself.
    if scan.sensor[i].distance(points[i]) < scan.range_noise {
        return footprint_patch(points, scan, i, toward_sensor);
    }
    let candidates = candidates(scan, i);
    let spans_surface = |neighborhood: &ScanNeighborhood| {
        let seen_face_on = neighborhood.normal.dot(toward_sensor).abs() >= EDGE_ON_COSINE;
        neighborhood.crosses_lines && neighborhood.members.len() >= 3 && seen_face_on
    };
    let fitted = neighborhood_agreeing_with(points, scan, i, &candidates, (chooser, fitted_normals[i]));
    let mut normal = smoothed_normal(&fitted, fitted_normals);
    if spans_surface(&fitted) && fitted.spread_over_noise(points, scan, i) > MAX_SPREAD {
        match level_fit(points, scan, i, &candidates) {
            LevelFit::On(level) => normal = level,
            LevelFit::Between(face) => {
                return line_patch(points, scan, i, &candidates.along, toward_sensor, face);
            }
            LevelFit::Unknown => {}
        }
    }
    let neighborhood = ScanNeighborhood { normal, ..fitted };
    if spans_surface(&neighborhood) && stretch_confirmed(&neighborhood, fitted_normals, toward_sensor) {
        let ellipse = surface_patch(points, scan, i, &neighborhood, toward_sensor);
        let cut = ellipse
            .cut_by_passing_rays(points, scan, i, &neighborhood.members, MAX_RISE)
            .cut_at_steps(points, scan, i);
        ScanPatch::over_surface(cut)
    } else {
        footprint_patch(points, scan, i, toward_sensor)
    }
}

/// Whether the returns around a point confirm the plane of its neighbourhood where the sensor
/// sees that plane so obliquely (`OBLIQUE_COSINE`) that its patch would stretch across the
/// lines to several footprints. A road seen far off is one plane, which the returns all along
/// it fit: `AGREEMENT_SHARE` of the members fitted planes of their own within about 25° of it.
/// A few returns in a bush or a tree top also span some plane through the point, seen edge-on
/// by chance, which each of them fits differently; stretched, such planes are the metre-long
/// shards a chase camera sees, so the return gets a footprint instead. A level plane below the
/// sensor stretches regardless: a car's roof or a sidewalk beside a kerb bends its members'
/// planes, and from above a footprint facing the sensor leaves it open. Above the sensor, a
/// level plane seen edge-on from below is far more often a tree's crown than a ceiling.
fn stretch_confirmed(neighborhood: &ScanNeighborhood, fitted_normals: &[Vec3], toward_sensor: Vec3) -> bool {
    let normal = neighborhood.normal;
    let level_below_sensor = normal.z.abs() >= LEVEL_COSINE && toward_sensor.z > 0.0;
    if normal.dot(toward_sensor).abs() >= OBLIQUE_COSINE || level_below_sensor {
        return true;
    }
    let members = &neighborhood.members;
    let agreeing =
        members.iter().filter(|&&j| fitted_normals[j as usize].dot(normal).abs() >= AGREEMENT_COSINE);
    agreeing.count() as f32 >= AGREEMENT_SHARE * members.len() as f32
}

/// A patch over the surface its neighbours agree on: the plane through the return that fits
/// them, over an ellipse that reaches the next return along the line on one axis and the next
/// line on the other. Through the return, not their centroid, so that the sensor's own ray
/// meets the patch where it met the surface.
fn surface_patch(
    points: &[Vec3],
    scan: &ScanLines,
    i: usize,
    neighborhood: &ScanNeighborhood,
    toward_sensor: Vec3,
) -> Ellipse {
    let normal = bridgeable(neighborhood.normal, toward_sensor);
    let along = along_line_direction(points, scan, i, &neighborhood.members, normal);
    let axes = TangentFrame { t1: along, t2: normal.cross(along), n: normal };
    let on_line = |j: u32| scan.line_of[j as usize] == scan.line_of[i];
    let local = |j: u32| axes.to_local(points[j as usize] - points[i]);
    let members = || neighborhood.members.iter().copied();
    let along_spacing = spacing(members().filter(|&j| on_line(j)).map(|j| local(j).x));
    let interleaving = INTERLEAVE_SIGMAS * scan.range_noise * toward_sensor.dot(axes.t2).abs();
    let across_spacing = line_gap(members().filter(|&j| !on_line(j)).map(|j| local(j).y), interleaving);
    let range = scan.sensor[i].distance(points[i]);
    let incidence = normal.dot(toward_sensor);
    let horizontal_range = (points[i] - scan.sensor[i]).truncate().length();
    let predicted_across = predicted_spacing(scan.beam_spacing(i), range, incidence);
    let predicted_along = predicted_spacing(scan.azimuth_step(i), horizontal_range, incidence);
    let (along_edge, across_edge) = silhouettes(points, scan, i, &neighborhood.members);
    let across_spacing = reach(across_spacing, predicted_across, across_edge);
    let along_spacing = if along_spacing > 0.0 { along_spacing } else { across_spacing };
    let along_spacing = reach(along_spacing, predicted_along, along_edge);
    let (major, radii) = if along_spacing >= across_spacing {
        (axes.t1, Vec2::new(along_spacing, across_spacing) * COVER)
    } else {
        (axes.t2, Vec2::new(across_spacing, along_spacing) * COVER)
    };
    Ellipse { centre: points[i], normal, major, radii }
}

/// `normal` facing the sensor, turned toward it where the sensor sees its plane more nearly
/// edge-on than `MIN_INCIDENCE_COSINE`: no reach is trusted past the spacing the beams have at
/// that incidence, so a patch any flatter (a car's roof seen from beside it) would leave its
/// lines open from the sensor. The turn is under 3°.
fn bridgeable(normal: Vec3, toward_sensor: Vec3) -> Vec3 {
    let normal = if normal.dot(toward_sensor) < 0.0 { -normal } else { normal };
    let cosine = normal.dot(toward_sensor);
    if cosine >= MIN_INCIDENCE_COSINE {
        return normal;
    }
    let Some(across) = (normal - cosine * toward_sensor).try_normalize() else { return normal };
    let sine = (1.0 - MIN_INCIDENCE_COSINE * MIN_INCIDENCE_COSINE).sqrt();
    MIN_INCIDENCE_COSINE * toward_sensor + sine * across
}

/// The direction from the previous to the next return on the point's line, in the tangent
/// plane; any tangent when the line offers none.
fn along_line_direction(points: &[Vec3], scan: &ScanLines, i: usize, members: &[u32], normal: Vec3) -> Vec3 {
    let along = line_sum(points, scan, i, members);
    (along - along.dot(normal) * normal).try_normalize().unwrap_or_else(|| normal_basis(normal).0)
}

/// The offsets from point `i` to the `members` on its own line, summed with the signs that
/// point them all one way along it.
fn line_sum(points: &[Vec3], scan: &ScanLines, i: usize, members: &[u32]) -> Vec3 {
    let line = scan.line_of[i];
    members
        .iter()
        .filter(|&&j| scan.line_of[j as usize] == line)
        .map(|&j| {
            let d = points[j as usize] - points[i];
            // Both sides point the same way once signed by azimuth order.
            if scan.azimuth[j as usize] >= scan.azimuth[i] { d } else { -d }
        })
        .sum()
}

/// The larger of the nearest positive and the nearest negative coordinate: each side's gap
/// to the next return, covering the wider; 0 when there is none.
fn spacing(coordinates: impl Iterator<Item = f32>) -> f32 {
    let (mut positive, mut negative) = (f32::INFINITY, f32::INFINITY);
    for c in coordinates {
        if c > 0.0 {
            positive = positive.min(c);
        } else if c < 0.0 {
            negative = negative.min(-c);
        }
    }
    match (positive.is_finite(), negative.is_finite()) {
        (true, true) => positive.max(negative).min(3.0 * positive.min(negative)),
        (true, false) => positive,
        (false, true) => negative,
        (false, false) => 0.0,
    }
}

/// The gap to the next lines from the `across` offsets of the returns on other lines: only
/// those further out than `interleaving` count, unless none is. Nearer ones may lie on either
/// side of the point, whatever their line, once the range noise moves returns across the lines
/// by about their spacing (a 128-beam sensor's road beside the car): taken for the next line,
/// they held the patch to a sliver and left holes between the lines.
fn line_gap(across: impl Iterator<Item = f32> + Clone, interleaving: f32) -> f32 {
    let beyond_noise = spacing(across.clone().filter(|offset| offset.abs() >= interleaving));
    if beyond_noise > 0.0 { beyond_noise } else { spacing(across) }
}

/// The spacing between returns that the sensor's angular step (between lines, or along one)
/// predicts at this range (about the step's axis) and incidence.
fn predicted_spacing(angular_step: Option<f32>, range: f32, incidence_cosine: f32) -> Option<f32> {
    Some(angular_step? * range / incidence_cosine.abs().max(MIN_INCIDENCE_COSINE))
}

/// How far a patch reaches on one axis, from the `spacing` to the next return on it: held to
/// what the sensor's step predicts (`PREDICTED_SPACING_TRUST`: past it the next return lies
/// beyond a dropout, an occluder or on another object); short of the next ray at an occluder's
/// edge; under the occluder, past the corners of its cells, on the surface it hides.
fn reach(spacing: f32, predicted: Option<f32>, silhouette: Silhouette) -> f32 {
    let Some(predicted) = predicted else { return spacing };
    let spacing = spacing.min(PREDICTED_SPACING_TRUST * predicted);
    match silhouette {
        Silhouette::None => spacing,
        Silhouette::InFront => spacing.min(IN_FRONT_REACH * predicted),
        Silhouette::Behind => spacing.max(BEHIND_REACH * predicted),
    }
}

/// A step's face reaches its levels along its across axis no further than if it were tilted
/// this far from their normal (60°): a face seen that obliquely is as likely a ramp.
const MAX_FACE_TILT_COSINE: f32 = 0.5;

/// A face patch reaches this multiple of the spacing along its line, and this multiple of the
/// step's height across it: the ellipses of neighbouring returns narrow toward the levels, and
/// must still meet there, where the levels' patches hide what they overreach.
const FACE_COVER: f32 = 1.5;
const FACE_OVERREACH: f32 = 1.15;

/// Returns on the point's own line this many azimuth steps away or nearer give a line patch
/// its direction.
const LINE_STEPS: f32 = 2.5;

/// A patch over a return on the face of a step, which its line alone sees: of the planes that
/// contain the line, the one the sensor sees most nearly face-on (returns are likeliest where
/// it is), over the return's angular cell along the line and from the level below to the
/// level above across it. A footprint where the line gives no direction.
fn line_patch(
    points: &[Vec3],
    scan: &ScanLines,
    i: usize,
    along: &[u32],
    toward_sensor: Vec3,
    face: StepFace,
) -> ScanPatch {
    let reach = LINE_STEPS * scan.azimuth_step(i).unwrap_or(0.0);
    let near: Vec<u32> = along
        .iter()
        .copied()
        .filter(|&j| (scan.azimuth[j as usize] - scan.azimuth[i]).abs() <= reach)
        .collect();
    let direction = face.along.or_else(|| line_sum(points, scan, i, &near).try_normalize());
    let normal = direction.and_then(|d| (toward_sensor - toward_sensor.dot(d) * d).try_normalize());
    let (Some(direction), Some(normal)) = (direction, normal) else {
        return footprint_patch(points, scan, i, toward_sensor);
    };
    let range = scan.sensor[i].distance(points[i]);
    let incidence = normal.dot(toward_sensor).max(MIN_INCIDENCE_COSINE);
    let step_along = spacing(near.iter().map(|&j| (points[j as usize] - points[i]).dot(direction)));
    // Across the line the face runs up to the level above and down to the level below, but
    // not past the next lines' rays.
    let up_axis = normal.cross(direction);
    let up_axis = if up_axis.dot(face.up) < 0.0 { -up_axis } else { up_axis };
    let tilt = up_axis.dot(face.up).max(MAX_FACE_TILT_COSINE);
    let cell = scan.beam_spacing(i).unwrap_or(0.0) * range / incidence;
    let (down, up) = ((face.below / tilt).min(cell), (face.above / tilt).min(cell));
    let centre = points[i] + up_axis * ((up - down) * 0.5);
    let radii = Vec2::new((up + down) * 0.5 * FACE_OVERREACH, step_along * FACE_COVER);
    let (major_axis, radii) =
        if radii.x >= radii.y { (up_axis, radii) } else { (direction, Vec2::new(radii.y, radii.x)) };
    let radii = radii.max(Vec2::splat(f32::MIN_POSITIVE));
    let frame = PackedTangentFrame::new(normal, major_axis);
    let fit = PatchFit { coefficients: [0.0; 6], kind: FitKind::Flat };
    ScanPatch { centre, normal, frame, radii, fit, on_surface: false }
}

/// A small flat ellipse facing the sensor over the return's own angular cell (the beam
/// spacing across lines, the azimuth step along them): where neighbours agree on no surface
/// (vegetation, edges, isolated returns), nothing wider is justified, and from the sensor
/// these cells tile what it saw without gaps. Each radius is `FOOTPRINT_COVER` steps, so
/// that the cell's corners are covered too.
fn footprint_patch(points: &[Vec3], scan: &ScanLines, i: usize, toward_sensor: Vec3) -> ScanPatch {
    // A return nearer its sensor than the range noise (one at the sensor itself) still covers
    // a footprint: the store refuses patches of no size.
    let range = scan.sensor[i].distance(points[i]).max(scan.range_noise);
    let across = scan.beam_spacing(i).or(scan.azimuth_step(i)).unwrap_or(0.0);
    let along = scan.azimuth_step(i).unwrap_or(across);
    let radii = Vec2::new(across, along) * FOOTPRINT_COVER * range;
    // Across the lines is up for a spinning sensor: the major axis lies in the vertical plane
    // through the ray, unless that plane is undefined (a ray straight up or down).
    let up_in_plane = Vec3::Z - Vec3::Z.dot(toward_sensor) * toward_sensor;
    let across_axis = up_in_plane.try_normalize().unwrap_or_else(|| normal_basis(toward_sensor).0);
    let (major_axis, radii) = if radii.x >= radii.y {
        (across_axis, radii)
    } else {
        (toward_sensor.cross(across_axis), Vec2::new(radii.y, radii.x))
    };
    let radii = radii.max(Vec2::splat(f32::MIN_POSITIVE));
    let frame = PackedTangentFrame::new(toward_sensor, major_axis);
    let fit = PatchFit { coefficients: [0.0; 6], kind: FitKind::Flat };
    ScanPatch { centre: points[i], normal: toward_sensor, frame, radii, fit, on_surface: false }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A neighbourhood of `members` 0..n on a plane of `normal`, whose own fitted planes are
    /// `fitted`, seen from the sensor along `toward_sensor`.
    fn stretch(normal: Vec3, fitted: &[Vec3], toward_sensor: Vec3) -> bool {
        let members = (0..fitted.len() as u32).collect();
        let neighborhood = ScanNeighborhood { members, normal: normal.normalize(), crosses_lines: true };
        stretch_confirmed(&neighborhood, fitted, toward_sensor.normalize())
    }

    #[test]
    fn an_oblique_plane_stretches_only_where_its_members_planes_agree_or_it_is_level_below_the_sensor() {
        let wall_along_the_ray = Vec3::Y;
        let grazing = Vec3::new(-1.0, 0.1, 0.0);
        let agreeing = [Vec3::Y, Vec3::new(0.2, 1.0, 0.0).normalize(), -Vec3::Y];
        let scattered = [Vec3::X, Vec3::Z, Vec3::Y];
        assert!(stretch(wall_along_the_ray, &agreeing, grazing));
        assert!(!stretch(wall_along_the_ray, &scattered, grazing), "a bush's chance plane");
        assert!(stretch(wall_along_the_ray, &scattered, Vec3::new(-1.0, 1.0, 0.0)), "seen face-on");
        let road_far_off = Vec3::new(-1.0, 0.0, 0.05);
        assert!(stretch(Vec3::Z, &scattered, road_far_off), "level planes below stretch regardless");
        let crown_overhead = Vec3::new(-1.0, 0.0, -0.05);
        assert!(!stretch(Vec3::Z, &scattered, crown_overhead), "a level plane above is no road");
    }

    #[test]
    fn returns_within_the_noise_do_not_set_the_gap_to_the_next_lines() {
        let across = [0.004, -0.03, 0.04];
        let all = line_gap(across.into_iter(), 0.0);
        assert!((all - 0.012).abs() < 1e-6, "three times the nearest, {all}");
        assert_eq!(line_gap(across.into_iter(), 0.02), 0.04);
    }

    #[test]
    fn when_every_return_lies_within_the_noise_they_all_count() {
        let across = [0.004, -0.006];
        assert_eq!(line_gap(across.into_iter(), 0.02), 0.006);
    }
}
