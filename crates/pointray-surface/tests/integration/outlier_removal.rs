//! Statistical outlier removal in `prep`: stray points far off a surface go, the surface stays.

use crate::common;

use glam::DVec3;
use pointray_patches::{OutlierFilter, PrepSettings};
use pointray_surface::{NoProgress, prep};

const PLANE_SIDE: usize = 60;
const OUTLIERS: usize = 20;

/// A jittered 60x60 plane at z = 0 over [-1, 1]², then 20 points 0.5 to 2 above or below it.
fn plane_with_outliers() -> pointray_io::PointCloud {
    let mut cloud = common::height_field(PLANE_SIDE, DVec3::ZERO, |_, _| 0.0);
    for i in 0..OUTLIERS {
        let (x, y) = (1.6 * common::jitter(1000 + 3 * i), 1.6 * common::jitter(1001 + 3 * i));
        let height = 1.25 + 1.5 * common::jitter(1002 + 3 * i);
        let side = if i % 2 == 0 { 1.0 } else { -1.0 };
        cloud.positions.push(DVec3::new(x, y, side * height));
    }
    cloud
}

#[test]
fn every_injected_outlier_goes_and_every_plane_point_stays() {
    let cloud = plane_with_outliers();
    let options = PrepSettings {
        remove_outliers: Some(OutlierFilter { neighbors: 8, sigmas: 2.0 }),
        ..PrepSettings::default()
    };
    let (patches, report) = prep(&cloud, &options, &NoProgress).expect("the plane preps");
    let plane_points = PLANE_SIDE * PLANE_SIDE;
    assert_eq!(report.removed_outliers, OUTLIERS);
    assert_eq!(patches.len(), plane_points);
    assert!(
        report.patch_sources.iter().all(|&source| (source as usize) < plane_points),
        "an injected outlier kept its patch"
    );
    assert!(report.to_string().contains(&format!("{OUTLIERS} outliers removed")), "{report}");
}

#[test]
fn without_the_filter_the_outliers_get_patches() {
    let (patches, report) = prep(&plane_with_outliers(), &PrepSettings::default(), &NoProgress).unwrap();
    assert_eq!(report.removed_outliers, 0);
    assert_eq!(patches.len(), PLANE_SIDE * PLANE_SIDE + OUTLIERS);
}

#[test]
fn bad_filter_settings_are_refused() {
    let options = PrepSettings {
        remove_outliers: Some(OutlierFilter { neighbors: 0, sigmas: 2.0 }),
        ..PrepSettings::default()
    };
    let error = prep(&plane_with_outliers(), &options, &NoProgress).unwrap_err();
    assert!(error.to_string().contains("remove_outliers.neighbors"), "{error}");
}
