//! A COPC file and the LAS it was written from (`data/scans/autzen_trim.copc.laz`, written by
//! copclib from `autzen_trim.las`) prep to the same patches up to point order: their points
//! put in one order, whole and tiled prep write the same patches bit for bit. Prep itself
//! depends on the order (its recentring offset is taken from a strided sample of the
//! points), so the order is made the same before prep rather than ignored after it.

use std::cmp::Ordering;

use pointray_io::PointCloud;
use pointray_io::formats::read_point_cloud;
use pointray_patches::PrepSettings;
use pointray_surface::tiles::tiled_prep::prep_tiled;
use pointray_surface::{NoProgress, prep};

fn read(relative: &str) -> PointCloud {
    read_point_cloud(&pointray_test_support::data_file(relative)).unwrap()
}

/// `cloud`'s points sorted by position, then colour, intensity and class.
fn in_one_order(cloud: &PointCloud) -> PointCloud {
    let colors = cloud.colors.as_ref().expect("colours");
    let intensities = cloud.intensities.as_ref().expect("intensities");
    let classes = cloud.classifications.as_ref().expect("classes");
    let position = |i: usize| cloud.positions[i].to_array();
    let compare = |&a: &usize, &b: &usize| -> Ordering {
        let by_position =
            position(a).iter().zip(position(b)).map(|(p, q)| p.total_cmp(&q)).find(|o| o.is_ne());
        by_position
            .unwrap_or(Ordering::Equal)
            .then(colors[a].cmp(&colors[b]))
            .then(intensities[a].total_cmp(&intensities[b]))
            .then(classes[a].cmp(&classes[b]))
    };
    let mut order: Vec<usize> = (0..cloud.len()).collect();
    order.sort_unstable_by(compare);
    PointCloud {
        colors: Some(order.iter().map(|&i| colors[i]).collect()),
        intensities: Some(order.iter().map(|&i| intensities[i]).collect()),
        classifications: Some(order.iter().map(|&i| classes[i]).collect()),
        ..PointCloud::from_positions(order.iter().map(|&i| cloud.positions[i]).collect())
    }
}

#[test]
fn copc_and_its_las_prep_to_the_same_patches() {
    let (copc, las) =
        (in_one_order(&read("scans/autzen_trim.copc.laz")), in_one_order(&read("scans/autzen_trim.las")));
    assert_eq!(copc, las, "the same points");
    let settings = PrepSettings::default();
    let whole = |cloud: &PointCloud| prep(cloud, &settings, &NoProgress).unwrap().0;
    let (copc_patches, las_patches) = (whole(&copc), whole(&las));
    assert!(copc_patches.len() > 100_000 && !copc_patches.color_neighbors.is_empty());
    assert!(copc_patches == las_patches, "whole prep");
    let tiled = |cloud: &PointCloud| prep_tiled(cloud, &settings, 4, &NoProgress).unwrap();
    assert!(tiled(&copc) == tiled(&las), "tiled prep");
}
