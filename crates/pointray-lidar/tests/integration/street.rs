//! The procedural street: its surfaces and classes, a scan of it, and the models on the road.

use pointray_lidar::street::{KERB_HEIGHT, ROAD_HALF_WIDTH, street};
use pointray_lidar::{Classification, LidarScene, NoProgress, SensorPreset, UpAxis, merged_mesh, scan};

use crate::common::*;

#[test]
fn a_scan_of_the_street_sees_ground_buildings_and_cars_where_they_are() {
    let surfaces = street(None).unwrap();
    let mesh = merged_mesh(&surfaces);
    assert_eq!(mesh.triangles.len(), surfaces.iter().map(|s| s.mesh.triangles.len()).sum::<usize>());
    let scene = LidarScene::from_surfaces(&surfaces, UpAxis::Z).unwrap();
    let sensor = exact(SensorPreset::Hdl32, 2.0);
    let scanned = scan(&scene, &sensor, &[station(0.0, 0.0, sensor.mount_height)], 1, &NoProgress).unwrap();
    let count = |class| scanned.returns.iter().filter(|r| r.classification == class).count();
    for class in [Classification::GROUND, Classification::BUILDING, Classification::VEHICLE] {
        assert!(count(class) > 50, "{class:?}: {} returns", count(class));
    }
    for r in &scanned.returns {
        let p = r.position;
        match r.classification {
            Classification::GROUND => {
                let on_road = p.y.abs() <= f64::from(ROAD_HALF_WIDTH) + 1e-3 && p.z.abs() < 1e-3;
                let on_sidewalk = (p.z - f64::from(KERB_HEIGHT)).abs() < 1e-3;
                let on_kerb = (p.y.abs() - f64::from(ROAD_HALF_WIDTH)).abs() < 1e-3;
                assert!(on_road || on_sidewalk || on_kerb, "ground return at {p}");
            }
            Classification::BUILDING => assert!(p.y.abs() > 7.3 && p.z > 0.1, "building return at {p}"),
            Classification::VEHICLE => assert!(p.y.abs() < 4.9 && p.z < 1.5, "car return at {p}"),
            _ => {}
        }
    }
}

#[test]
fn the_scanned_models_stand_on_the_road_a_metre_tall_or_long() {
    let data = pointray_test_support::data_dir();
    let surfaces = street(Some(&data)).unwrap();
    for name in ["bunny", "horse"] {
        let model = surfaces.iter().find(|s| s.name == name).unwrap_or_else(|| panic!("no {name}"));
        let (lo, hi) = model
            .mesh
            .positions
            .iter()
            .fold((glam::Vec3::INFINITY, glam::Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        assert!(lo.z.abs() < 1e-5, "{name} floats at {}", lo.z);
        assert!(((hi - lo).max_element() - 1.0).abs() < 1e-4, "{name} is {} across", (hi - lo).max_element());
        assert!(hi.y.abs().max(lo.y.abs()) < ROAD_HALF_WIDTH, "{name} is off the road");
        assert_eq!(Classification::of_object_named(name), Classification::UNCLASSIFIED);
    }
}
