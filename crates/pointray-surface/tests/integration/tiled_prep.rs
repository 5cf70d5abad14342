//! Prep in tiles with halos makes the patches a single pass makes: the same count, equal
//! positions, normals and coefficients within the record's quantisation, the same colours
//! and colour neighbours.

use std::collections::HashMap;

use glam::DVec3;
use pointray_io::PointCloud;
use pointray_kernels::interpolate_color::COLOR_NEIGHBORS;
use pointray_patches::{PatchSet, PrepSettings, ScanMode};
use pointray_surface::tiles::tiled_prep::{TilePlan, prep_tile, prep_tiled};
use pointray_surface::{NoProgress, PrepError, prep};

use crate::common::{height_field, jitter};

/// A wavy, coloured sheet seen from above, with a few stray returns floating over it: normals
/// toward the sensor depend only on each point's neighbourhood, as the fits and supports do. A
/// stray point's neighbours lie far off on the sheet, so its tile's halo must reach that far.
pub fn coloured_sheet() -> (PointCloud, PrepSettings) {
    let shift = DVec3::new(500.0, -200.0, 30.0);
    let mut cloud = height_field(110, shift, |x, y| 0.2 * (3.0 * x).sin() * (2.0 * y).cos());
    for i in 0..12 {
        let (x, y) = (1.6 * jitter(3 * i + 7), 1.6 * jitter(3 * i + 8));
        cloud.positions.push(shift + DVec3::new(x, y, 0.5 + 0.3 * jitter(3 * i + 9)));
    }
    let colors = (0..cloud.len()).map(|i| [(i % 251) as u8, (jitter(i) * 200.0 + 100.0) as u8, 40]).collect();
    cloud.colors = Some(colors);
    let options = PrepSettings {
        sensor: Some(DVec3::new(500.0, -200.0, 40.0)),
        scan: ScanMode::Off,
        ..PrepSettings::default()
    };
    (cloud, options)
}

fn position_key(set: &PatchSet, i: usize) -> [u32; 3] {
    set.hot[i].origin().to_array().map(f32::to_bits)
}

#[test]
fn eight_tiles_make_the_single_pass_patches() {
    let (cloud, options) = coloured_sheet();
    let (whole, _) = prep(&cloud, &options, &NoProgress).expect("a single pass preps");
    let tiled = prep_tiled(&cloud, &options, 8, &NoProgress).expect("eight tiles prep");
    assert_eq!(tiled.len(), whole.len(), "one patch per point either way");
    assert_eq!(tiled.offset, whole.offset, "the whole cloud's offset");
    let index: HashMap<[u32; 3], usize> = (0..whole.len()).map(|i| (position_key(&whole, i), i)).collect();
    assert_eq!(index.len(), whole.len(), "positions tell the patches apart");
    let (mut normal_error, mut coefficient_error) = (0.0f32, 0.0f32);
    for t in 0..tiled.len() {
        let w = *index.get(&position_key(&tiled, t)).unwrap_or_else(|| panic!("tiled patch {t} has no twin"));
        let (a, b) = (tiled.hot[t].decode(), whole.hot[w].decode());
        normal_error = normal_error.max(a.frame.n.angle_between(b.frame.n));
        assert!((a.radii - b.radii).abs().max_element() <= 1e-3 * b.radii.x, "patch {t}: radii");
        let scale = b.radii.x;
        for (c, d) in a.coefficients.iter().zip(b.coefficients) {
            coefficient_error = coefficient_error.max((c - d).abs() * scale);
        }
        assert_eq!(tiled.aabbs[t], whole.aabbs[w], "patch {t}: box");
        assert_eq!(tiled.cold[t], whole.cold[w], "patch {t}: colour, intensity and reach");
        let neighbour_positions = |set: &PatchSet, i: usize| -> Vec<[u32; 3]> {
            set.color_neighbors[i * COLOR_NEIGHBORS..(i + 1) * COLOR_NEIGHBORS]
                .iter()
                .map(|&j| position_key(set, j as usize))
                .collect()
        };
        assert_eq!(
            neighbour_positions(&tiled, t),
            neighbour_positions(&whole, w),
            "patch {t}: colour neighbours"
        );
    }
    eprintln!(
        "8 tiles against one pass: normals within {normal_error:e} rad, coefficients within {coefficient_error:e}"
    );
    // One step of the octahedral normal's snorm11 codes is about 1e-3 rad, so the normals'
    // codes must be equal; the half-float coefficients, scaled by the radius, resolve about
    // 1e-3 of it.
    assert!(normal_error <= 1e-4, "normals differ by {normal_error} rad");
    assert!(coefficient_error <= 1e-3, "coefficients differ by {coefficient_error}");
}

#[test]
fn a_tile_past_the_last_is_refused() {
    let (cloud, options) = coloured_sheet();
    let plan = TilePlan::new(&cloud, &options, 4);
    let error = prep_tile(&cloud, &options, &plan, 4, &NoProgress).expect_err("tile 4 of 4");
    assert!(matches!(error, PrepError::NoSuchTile { index: 4, count: 4 }), "{error}");
    assert!(error.to_string().contains("cut into 4 tiles (0 to 3)"), "{error}");
}

#[test]
fn tiles_of_a_cloud_with_duplicates_make_the_single_pass_patches() {
    let (mut cloud, options) = coloured_sheet();
    // Every third point comes twice: overlapping scans hold such duplicates, which prep
    // merges, so a point's neighbours in the merged cloud lie farther than among the raw points
    // and the halo must reach that far.
    let doubled: Vec<usize> = (0..cloud.len()).step_by(3).collect();
    let positions: Vec<DVec3> = doubled.iter().map(|&i| cloud.positions[i]).collect();
    let colors: Vec<[u8; 3]> = doubled.iter().map(|&i| cloud.colors.as_ref().unwrap()[i]).collect();
    cloud.positions.extend(positions);
    cloud.colors.as_mut().unwrap().extend(colors);
    let (whole, report) = prep(&cloud, &options, &NoProgress).expect("a single pass preps");
    assert!(report.merged_duplicates > 1000, "{} merged", report.merged_duplicates);
    let tiled = prep_tiled(&cloud, &options, 8, &NoProgress).expect("eight tiles prep");
    let index: HashMap<[u32; 3], usize> = (0..whole.len()).map(|i| (position_key(&whole, i), i)).collect();
    let mut twins = vec![0; whole.len()];
    for t in 0..tiled.len() {
        let w = *index.get(&position_key(&tiled, t)).unwrap_or_else(|| panic!("tiled patch {t} has no twin"));
        twins[w] += 1;
        assert_eq!(tiled.aabbs[t], whole.aabbs[w], "patch {t}: box");
        assert_eq!(tiled.cold[t], whole.cold[w], "patch {t}: colour, intensity and reach");
    }
    assert!(twins.iter().all(|&n| n >= 1), "every single-pass patch has a tiled twin");
    // A duplicate pair that a tile cut separates is kept by both tiles (each keeps its own
    // copy first): at most one extra patch per cut.
    let extra = tiled.len() - whole.len();
    assert!(extra < 8, "{extra} patches more than a single pass");
}

/// A plane beside a long straight row of points (a wire, say), the row last along the curve.
fn plane_and_row() -> Vec<DVec3> {
    let plane = (0..90_000).map(|i| DVec3::new((i % 300) as f64, (i / 300) as f64, 0.0) * 0.01);
    let row = (0..90_000).map(|i| DVec3::new(10.0 + i as f64 * 1e-4, 5.0, 5.0));
    plane.chain(row).collect()
}

#[test]
fn a_tile_on_one_line_is_no_fault_of_a_cloud_that_is_not() {
    let cloud = PointCloud::from_positions(plane_and_row());
    let tiled = prep_tiled(&cloud, &PrepSettings::default(), 2, &NoProgress).expect("two tiles prep");
    assert_eq!(tiled.hot.len(), cloud.len());
}

#[test]
fn every_tile_of_a_cloud_on_one_line_refuses_it_whole() {
    let line: Vec<DVec3> = (0..20_000).map(|i| DVec3::new(1.0, 0.5, 0.25) * i as f64).collect();
    let cloud = PointCloud::from_positions(line);
    let plan = TilePlan::new(&cloud, &PrepSettings::default(), 3);
    for index in 0..3 {
        let error = prep_tile(&cloud, &PrepSettings::default(), &plan, index, &NoProgress).unwrap_err();
        assert_eq!(error, PrepError::AllPointsCollinear { count: 20_000 }, "tile {index}");
    }
}
