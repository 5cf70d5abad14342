//! Adaptive support radii on a plane whose density jumps tenfold: the disks cover the seam,
//! and no radius leaves the band around its neighbourhood's median.

use crate::common;

use glam::{DVec3, Vec2};
use pointray_patches::{PatchSet, PrepSettings, RadiusMode};
use pointray_surface::density_radius::BAND;
use pointray_surface::neighbors::k_nearest;
use pointray_surface::{NoProgress, prep};

/// Dense cell edge; the sparse half's cells are sqrt(10) times wider: 10x fewer points per area.
const DENSE_CELL: f64 = 0.02;

/// A jittered grid at z = 0: x in [-1, 0) at `DENSE_CELL`, x in [0, 1] ten times sparser.
fn density_jump() -> pointray_io::PointCloud {
    let mut positions = Vec::new();
    for (x_start, cell) in [(-1.0, DENSE_CELL), (0.0, DENSE_CELL * 10f64.sqrt())] {
        let columns = (1.0 / cell).round() as usize;
        let rows = (2.0 / cell).round() as usize;
        for row in 0..rows {
            for column in 0..columns {
                let i = positions.len();
                let x = x_start + cell * (column as f64 + 0.5 + 0.6 * common::jitter(2 * i));
                let y = -1.0 + cell * (row as f64 + 0.5 + 0.6 * common::jitter(2 * i + 1));
                positions.push(DVec3::new(x, y, 0.0));
            }
        }
    }
    pointray_io::PointCloud::from_positions(positions)
}

fn prepped(mode: RadiusMode) -> PatchSet {
    let options = PrepSettings { radius: mode, ..PrepSettings::default() };
    prep(&density_jump(), &options, &NoProgress).expect("the plane preps").0
}

/// Sample points of the seam strip (|x| <= 0.25, away from the outer border) that no
/// patch's disk reaches, measured in the plane (every normal is ±z here).
fn uncovered_seam_points(patches: &PatchSet) -> Vec<Vec2> {
    let disks: Vec<(Vec2, f32)> = patches
        .hot
        .iter()
        .map(|hot| ((hot.origin().as_dvec3() + patches.offset).truncate().as_vec2(), hot.radius()))
        .filter(|(centre, radius)| centre.x.abs() < 0.25 + radius)
        .collect();
    let step = 0.004;
    let samples = (0..=125)
        .flat_map(|i| (0..=400).map(move |j| Vec2::new(-0.25 + step * i as f32, -0.8 + step * j as f32)));
    samples.filter(|s| !disks.iter().any(|(centre, radius)| centre.distance(*s) <= *radius)).collect()
}

#[test]
fn adaptive_radii_cover_the_seam() {
    let patches = prepped(RadiusMode::Adaptive);
    assert!(patches.hot.iter().all(|hot| hot.normal().z.abs() > 0.999), "a plane's normals are ±z");
    let holes = uncovered_seam_points(&patches);
    assert!(
        holes.is_empty(),
        "{} seam points uncovered, e.g. {:?}",
        holes.len(),
        &holes[..holes.len().min(5)]
    );
}

#[test]
fn adaptive_radii_stay_in_the_band() {
    let (paper, adaptive) = (prepped(RadiusMode::Paper), prepped(RadiusMode::Adaptive));
    assert_eq!(paper.len(), adaptive.len());
    let k = PrepSettings::default().k as usize;
    let origins: Vec<_> = paper.hot.iter().map(|hot| hot.origin()).collect();
    let neighbors = k_nearest(&origins, k);
    let mut changed = 0;
    for i in 0..paper.len() {
        assert_eq!(paper.hot[i].origin(), adaptive.hot[i].origin(), "both modes keep the same order");
        let mut radii: Vec<f32> = std::iter::once(i as u32)
            .chain(neighbors.of(i).iter().copied())
            .map(|j| paper.hot[j as usize].radius())
            .collect();
        radii.sort_by(f32::total_cmp);
        let median = radii[radii.len() / 2];
        let d = adaptive.hot[i].radius();
        assert!(
            d <= BAND * median * 1.0001 && d >= median / BAND * 0.9999,
            "patch {i}: d = {d}, median {median}"
        );
        changed += usize::from(d != paper.hot[i].radius());
    }
    assert!(changed > 0, "the adaptive mode changed no radius at all");
}

/// A 40x40 plane at z = 0 over [-1, 1]² and one point 1 above its middle.
fn plane_with_a_stray_point() -> pointray_io::PointCloud {
    let mut cloud = common::height_field(40, DVec3::ZERO, |_, _| 0.0);
    cloud.positions.push(DVec3::new(0.0, 0.0, 1.0));
    cloud
}

#[test]
fn an_isolated_point_gets_no_huge_patch() {
    let stray = |mode| {
        let options = PrepSettings { radius: mode, ..PrepSettings::default() };
        let (patches, _) = prep(&plane_with_a_stray_point(), &options, &NoProgress).unwrap();
        let index =
            patches.hot.iter().position(|hot| (hot.origin().as_dvec3() + patches.offset).z > 0.5).unwrap();
        (patches.hot[index].radius(), patches.hot.iter().map(|hot| hot.radius()).fold(0.0, f32::max))
    };
    let cell = 2.0 / 40.0;
    let (paper, _) = stray(RadiusMode::Paper);
    assert!(paper > 0.5, "the paper's radius reaches the plane 1 away: {paper}");
    let (adaptive, largest) = stray(RadiusMode::Adaptive);
    assert!(adaptive < 6.0 * cell, "the stray point's patch is {adaptive} wide, the spacing {cell}");
    assert!(largest < 6.0 * cell, "no adaptive patch grew past a few spacings: {largest}");
}
