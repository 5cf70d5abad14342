//! Patches of a LiDAR scan (`ScanLines`): elliptical supports that reach halfway to the next
//! return along the scan line and halfway to the next line, fitted to neighbourhoods that span
//! lines; small disks facing the sensor where the neighbours agree on no surface.

use glam::{Vec2, Vec3};
use pointray_kernels::packed_frame::normal_basis;
use pointray_kernels::{PackedFrame, TangentFrame};
use rayon::prelude::*;

use crate::quadratic_fit::{FitKind, PatchFit, fit_plane_patch};
use crate::scan_lines::ScanLines;
use crate::scan_neighborhood::{ScanNeighborhood, agreeing_neighborhood, candidates};

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

/// A footprint patch reaches this many angular steps from its return: 1/√2 would just meet
/// the cell's corners on a regular grid; more covers the jitter of real azimuths.
const FOOTPRINT_COVER: f32 = 0.75;

/// The Wendland scale of the fit is this multiple of the farthest neighbour on each axis,
/// as in the unstructured fit.
const WENDLAND_SCALE: f32 = 1.1;

/// A scan patch before packing: its oriented normal, stored frame, radii `(d_u, d_v)` with
/// `d_u >= d_v`, and fit.
#[derive(Clone, Copy, Debug)]
pub struct ScanPatch {
    pub normal: Vec3,
    pub frame: PackedFrame,
    pub radii: Vec2,
    pub fit: PatchFit,
    /// Whether its neighbours agreed on a surface (else it is a small disk facing the sensor).
    pub on_surface: bool,
}

/// Every point's patch, in parallel.
pub fn scan_patches(points: &[Vec3], scan: &ScanLines) -> Vec<ScanPatch> {
    (0..points.len()).into_par_iter().with_min_len(1024).map(|i| scan_patch(points, scan, i)).collect()
}

fn scan_patch(points: &[Vec3], scan: &ScanLines, i: usize) -> ScanPatch {
    let candidates = candidates(scan, i);
    let neighborhood = agreeing_neighborhood(points, scan, i, &candidates);
    let toward_sensor = (scan.sensor[i] - points[i]).normalize_or(Vec3::Z);
    let seen_face_on = neighborhood.normal.dot(toward_sensor).abs() >= EDGE_ON_COSINE;
    if neighborhood.crosses_lines && neighborhood.members.len() >= 3 && seen_face_on {
        surface_patch(points, scan, i, &neighborhood, toward_sensor)
    } else {
        footprint_patch(points, scan, i, toward_sensor)
    }
}

/// A patch over the surface its neighbours agree on.
fn surface_patch(
    points: &[Vec3],
    scan: &ScanLines,
    i: usize,
    neighborhood: &ScanNeighborhood,
    toward_sensor: Vec3,
) -> ScanPatch {
    let normal =
        if neighborhood.normal.dot(toward_sensor) < 0.0 { -neighborhood.normal } else { neighborhood.normal };
    let along = along_line_direction(points, scan, i, &neighborhood.members, normal);
    let offsets: Vec<(Vec3, bool)> = neighborhood
        .members
        .iter()
        .map(|&j| (points[j as usize] - points[i], scan.line_of[j as usize] == scan.line_of[i]))
        .collect();
    let axes = TangentFrame { t1: along, t2: normal.cross(along), n: normal };
    let along_spacing = spacing(offsets.iter().filter(|(_, same)| *same).map(|(d, _)| axes.to_local(*d).x));
    let across_spacing = spacing(offsets.iter().filter(|(_, same)| !*same).map(|(d, _)| axes.to_local(*d).y));
    let range = scan.sensor[i].distance(points[i]);
    let incidence = normal.dot(toward_sensor);
    let across_spacing = cap_by_predicted(across_spacing, scan.beam_spacing(i), range, incidence);
    let along_spacing = if along_spacing > 0.0 { along_spacing } else { across_spacing };
    let horizontal_range = (points[i] - scan.sensor[i]).truncate().length();
    let along_spacing = cap_by_predicted(along_spacing, scan.azimuth_step(i), horizontal_range, incidence);
    let (major_axis, radii) = if along_spacing >= across_spacing {
        (axes.t1, Vec2::new(along_spacing, across_spacing) * COVER)
    } else {
        (axes.t2, Vec2::new(across_spacing, along_spacing) * COVER)
    };
    let frame = PackedFrame::new(normal, major_axis);
    let fit = elliptical_fit(&frame.decode(), &offsets, radii.x);
    ScanPatch { normal, frame, radii, fit, on_surface: true }
}

/// The direction from the previous to the next return on the point's line, in the tangent
/// plane; any tangent when the line offers none.
fn along_line_direction(points: &[Vec3], scan: &ScanLines, i: usize, members: &[u32], normal: Vec3) -> Vec3 {
    let line = scan.line_of[i];
    let along: Vec3 = members
        .iter()
        .filter(|&&j| scan.line_of[j as usize] == line)
        .map(|&j| {
            let d = points[j as usize] - points[i];
            // Both sides point the same way once signed by azimuth order.
            if scan.azimuth[j as usize] >= scan.azimuth[i] { d } else { -d }
        })
        .sum();
    (along - along.dot(normal) * normal).try_normalize().unwrap_or_else(|| normal_basis(normal).0)
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

/// A spacing between returns held to what the sensor's angular step (between lines, or along
/// one) predicts at this range (about the step's axis) and incidence: past it the next return
/// lies beyond a dropout, an occluder or on another object.
fn cap_by_predicted(spacing: f32, angular_step: Option<f32>, range: f32, incidence_cosine: f32) -> f32 {
    let Some(step) = angular_step else { return spacing };
    let incidence = incidence_cosine.abs().max(MIN_INCIDENCE_COSINE);
    spacing.min(PREDICTED_SPACING_TRUST * step * range / incidence)
}

/// The plane fit with Wendland weights over the support's own ellipse, so that returns on
/// the next line, farther away than those along the line, weigh as much at the same fraction
/// of the way to the edge. A plane, not a quadratic: a return has a dozen scan neighbours at
/// most, mostly along one line, and their range noise (centimetres) would become curvature
/// that bends the patch across the grazing rays of the ground.
fn elliptical_fit(frame: &TangentFrame, offsets: &[(Vec3, bool)], major_radius: f32) -> PatchFit {
    let locals: Vec<Vec3> = offsets.iter().map(|(d, _)| frame.to_local(*d)).collect();
    let reach = locals.iter().fold(Vec2::ZERO, |reach, l| reach.max(Vec2::new(l.x.abs(), l.y.abs())));
    let scales = (reach * WENDLAND_SCALE)
        .max(Vec2::splat(reach.max_element() * 0.1))
        .max(Vec2::splat(f32::MIN_POSITIVE));
    let h = scales.max_element();
    let samples = locals.iter().map(|&l| (l, h * (Vec2::new(l.x, l.y) / scales).length()));
    fit_plane_patch(std::iter::once((Vec3::ZERO, 0.0)).chain(samples), h, major_radius)
}

/// A small flat ellipse facing the sensor over the return's own angular cell (the beam
/// spacing across lines, the azimuth step along them): where neighbours agree on no surface
/// (vegetation, edges, isolated returns), nothing wider is justified, and from the sensor
/// these cells tile what it saw without gaps. Each radius is `FOOTPRINT_COVER` steps, so
/// that the cell's corners are covered too.
fn footprint_patch(points: &[Vec3], scan: &ScanLines, i: usize, toward_sensor: Vec3) -> ScanPatch {
    let range = scan.sensor[i].distance(points[i]);
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
    let frame = PackedFrame::new(toward_sensor, major_axis);
    let fit = PatchFit { coefficients: [0.0; 6], kind: FitKind::Flat };
    ScanPatch { normal: toward_sensor, frame, radii, fit, on_surface: false }
}
