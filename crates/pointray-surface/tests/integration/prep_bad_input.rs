//! `prep` refuses bad point sets with specific errors, and survives duplicates.

use crate::common;

use glam::DVec3;
use pointray_io::PointCloud;
use pointray_patches::PrepSettings;
use pointray_surface::tiles::tiled_prep::prep_tiled;
use pointray_surface::{NoProgress, PrepError, prep};

fn prep_error(positions: Vec<DVec3>) -> PrepError {
    let cloud = PointCloud::from_positions(positions);
    prep(&cloud, &PrepSettings::default(), &NoProgress).expect_err("bad input must be refused")
}

fn plane(n: usize) -> Vec<DVec3> {
    common::height_field(n, DVec3::ZERO, |x, y| 0.1 * x + 0.2 * y).positions
}

#[test]
fn nan_and_infinite_coordinates_name_the_point() {
    let mut positions = plane(10);
    positions[42].x = f64::NAN;
    let error = prep_error(positions.clone());
    assert_eq!(error, PrepError::NonFiniteCoordinate { index: 42 });
    assert!(error.to_string().contains("point 42"), "{error}");
    positions[42].x = 0.0;
    positions[17].z = f64::INFINITY;
    assert_eq!(prep_error(positions), PrepError::NonFiniteCoordinate { index: 17 });
}

#[test]
fn too_few_points_for_k() {
    // k shrinks to the other points, down to 3: fewer than 4 points are refused.
    assert_eq!(prep_error(plane(3)[..3].to_vec()), PrepError::TooFewPoints { found: 3, k: 3 });
    assert_eq!(prep_error(Vec::new()), PrepError::TooFewPoints { found: 0, k: 3 });
}

/// A cloud of fewer points than k + 1 (PCL's and pypcd4's test clouds hold 8) used to be
/// refused; it preps with k cut to the other points, which its store records.
#[test]
fn a_cloud_smaller_than_k_preps_with_the_neighbours_it_has() {
    let cloud = PointCloud::from_positions(plane(3));
    let (patches, report) = prep(&cloud, &PrepSettings::default(), &NoProgress).expect("9 points prep");
    assert_eq!((report.patches, patches.settings.k, patches.settings.normal_k), (9, 8, 8));
}

#[test]
fn too_few_distinct_points_after_merging() {
    // 12 points, but only 4 distinct ones.
    let corners = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    let positions: Vec<DVec3> = (0..12).map(|i| corners[i % 4]).collect();
    assert_eq!(prep_error(positions), PrepError::TooFewDistinctPoints { found: 4, k: 9 });
}

#[test]
fn identical_and_collinear_points() {
    let error = prep_error(vec![DVec3::new(1.0, 2.0, 3.0); 50]);
    assert_eq!(error, PrepError::AllPointsIdentical { count: 50 });
    assert!(error.to_string().contains("identical"));
    let line = (0..50).map(|i| DVec3::new(1.0, -2.0, 0.5) * f64::from(i) + DVec3::splat(7.0)).collect();
    let error = prep_error(line);
    assert_eq!(error, PrepError::AllPointsCollinear { count: 50 });
    assert!(error.to_string().contains("one line"));
}

#[test]
fn attribute_arrays_must_match_the_points() {
    let mut cloud = PointCloud::from_positions(plane(10));
    cloud.colors = Some(vec![[1, 2, 3]; 99]);
    let error = prep(&cloud, &PrepSettings::default(), &NoProgress).unwrap_err();
    assert_eq!(error, PrepError::AttributeLength { attribute: "colours", found: 99, expected: 100 });
}

#[test]
fn exact_and_near_duplicates_are_merged_without_nans_or_zero_radii() {
    // Away from the middle, where the cloud is recentred: there f32 steps are finer than the
    // 1e-9 between near copies, which stay apart by the rule. The copies differ along one
    // axis, so rounding to f32 leaves them at most one step apart.
    let base: Vec<DVec3> = plane(20).into_iter().filter(|p| p.x.abs().max(p.y.abs()) > 0.2).collect();
    let mut positions = base.clone();
    positions.extend(base.iter().step_by(2).copied()); // exact copies
    positions.extend(base.iter().skip(1).step_by(2).map(|p| *p + DVec3::X * 1e-9)); // 1e-9 apart
    let cloud = PointCloud::from_positions(positions);
    let (patches, report) = prep(&cloud, &PrepSettings::default(), &NoProgress).expect("duplicates are fine");
    assert_eq!(report.input_points, 2 * base.len());
    assert_eq!(report.merged_duplicates, base.len());
    assert_eq!(patches.len(), base.len());
    for patch in &patches.hot {
        let decoded = patch.decode();
        let values =
            decoded.origin.to_array().into_iter().chain(decoded.coefficients).chain(decoded.radii.to_array());
        assert!(values.into_iter().all(|v| v.is_finite()), "{patch:?}");
        assert!(patch.radius() > 0.0, "{patch:?}");
    }
}

/// A NaN intensity would reach the store's cold records, which every renderer refuses to
/// load: prep refuses it first, naming the point, whether it preps whole or in tiles.
#[test]
fn a_nan_intensity_is_refused_naming_its_point() {
    let mut cloud = PointCloud::from_positions(plane(20));
    let mut intensities = vec![0.5; cloud.len()];
    intensities[317] = f32::NAN;
    cloud.intensities = Some(intensities);
    let whole = prep(&cloud, &PrepSettings::default(), &NoProgress).unwrap_err();
    assert_eq!(whole, PrepError::NonFiniteIntensity { index: 317 });
    assert!(whole.to_string().contains("point 317 has an intensity"), "{whole}");
    let tiled = prep_tiled(&cloud, &PrepSettings::default(), 4, &NoProgress).unwrap_err();
    assert_eq!(tiled, PrepError::NonFiniteIntensity { index: 317 }, "the cloud's point, not the tile's");
}

/// A tile needs points of its own: library callers asking for more tiles than points get the
/// reason, as the command line's callers do, not empty tiles.
#[test]
fn more_tiles_than_points_are_refused_in_the_library() {
    let cloud = PointCloud::from_positions(plane(10));
    let error = prep_tiled(&cloud, &PrepSettings::default(), 101, &NoProgress).unwrap_err();
    assert_eq!(error, PrepError::TooManyTiles { tiles: 101, points: 100 });
    assert!(error.to_string().contains("101 tiles asked for"), "{error}");
    assert!(
        prep_tiled(&cloud, &PrepSettings::default(), 100, &NoProgress).is_ok(),
        "one point a tile is allowed"
    );
}
