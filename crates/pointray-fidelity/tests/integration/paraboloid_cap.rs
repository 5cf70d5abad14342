//! The exactness test: a paraboloid cap, a surface the quadratic patches fit almost
//! exactly, against its own triangulation. Then the same cap with points removed, to show
//! that the hole rate does move.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use pointray_fidelity::{CpuImageRenderer, FidelityOptions, FidelityReport, ViewSpec, measure_fidelity};
use pointray_io::{PointCloud, TriangleMesh};
use pointray_patches::PrepSettings;
use pointray_scene::PatchAcceptance;
use pointray_surface::{NoProgress, prep};

/// z = CURVATURE * (x² + y²) over the unit disc.
const CURVATURE: f64 = 0.5;
/// Grid samples along the [-1, 1] square. The mesh's flat facets differ from the smooth
/// surface by up to `2 * CURVATURE * spacing` radians (0.7°); its interpolated vertex
/// normals, which fidelity compares against, follow the smooth surface between vertices.
const GRID: usize = 161;
const SIZE: u32 = 128;

/// The grid vertices inside the unit disc on the paraboloid, and the triangles of the grid
/// cells whose vertices all lie inside.
fn paraboloid_cap() -> TriangleMesh {
    let spacing = 2.0 / (GRID - 1) as f64;
    let coordinate = |i: usize| -1.0 + i as f64 * spacing;
    let mut index = vec![None; GRID * GRID];
    let mut mesh = TriangleMesh::default();
    for (cell, slot) in index.iter_mut().enumerate() {
        let (x, y) = (coordinate(cell % GRID), coordinate(cell / GRID));
        if x * x + y * y <= 1.0 {
            *slot = Some(mesh.positions.len() as u32);
            mesh.positions.push(DVec3::new(x, y, CURVATURE * (x * x + y * y)).as_vec3());
        }
    }
    for row in 0..GRID - 1 {
        for column in 0..GRID - 1 {
            let corner = |dx: usize, dy: usize| index[(row + dy) * GRID + column + dx];
            if let (Some(a), Some(b), Some(c), Some(d)) =
                (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1))
            {
                mesh.triangles.extend([[a, b, c], [a, c, d]]);
            }
        }
    }
    mesh
}

/// The mesh's vertices as points, except those `keep` rejects.
fn points_of(mesh: &TriangleMesh, keep: impl Fn(Vec3) -> bool) -> PointCloud {
    PointCloud::from_positions(mesh.positions.iter().filter(|p| keep(**p)).map(|p| p.as_dvec3()).collect())
}

/// Straight down into the bowl, straight up at its underside, and four views from 45° above
/// the rim: every camera sees the cap's face rather than its edge.
fn views_that_see_the_cap() -> Vec<Vec3> {
    let oblique = |x: f32, y: f32| Vec3::new(x, y, 1.0).normalize();
    vec![Vec3::Z, Vec3::NEG_Z, oblique(1.0, 0.0), oblique(-1.0, 0.0), oblique(0.0, 1.0), oblique(0.0, -1.0)]
}

fn measure(points: &PointCloud, mesh: TriangleMesh) -> FidelityReport {
    let (patches, _) = prep(points, &PrepSettings::default(), &NoProgress).expect("prep of the cap");
    let views = views_that_see_the_cap().into_iter().map(ViewSpec::Direction).collect();
    let options = FidelityOptions::with_views(views, SIZE, PatchAcceptance::Box);
    let report = measure_fidelity(Arc::new(patches), Arc::new(mesh), &options, &CpuImageRenderer).unwrap();
    println!("{report}");
    report
}

#[test]
fn the_cap_has_no_holes_and_normals_within_a_twentieth_of_a_degree() {
    let mesh = paraboloid_cap();
    let report = measure(&points_of(&mesh, |_| true), mesh);
    let overall = &report.overall;
    assert!(overall.mesh_pixels > 6 * (SIZE * SIZE / 10) as u64, "the cap fills too little: {overall:?}");
    assert_eq!(overall.hole_rate, Some(0.0), "{overall:?}");
    assert!(overall.normal_error_mean_degrees.unwrap() < 0.05, "{overall:?}");
    assert!(report.views.iter().all(|view| view.metrics.hole_rate == Some(0.0)));
    assert_json_carries_the_numbers(&report);
}

/// The JSON file holds the same numbers as the report, with the setup and one entry per view.
fn assert_json_carries_the_numbers(report: &FidelityReport) {
    let directory = tempfile::tempdir().unwrap();
    let path = directory.path().join("fidelity.json");
    report.write_json(&path).unwrap();
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(json["overall"]["hole_rate"], serde_json::json!(0.0));
    // serde_json parses decimals to within an ulp, not always back to the same f64.
    let written = json["overall"]["normal_error_mean_degrees"].as_f64().expect("a number");
    let mean = report.overall.normal_error_mean_degrees.unwrap();
    assert!((written - mean).abs() <= 1e-12 * mean.abs(), "{written} against {mean}");
    assert_eq!(json["setup"]["acceptance"], "box");
    assert_eq!(json["views"].as_array().map(Vec::len), Some(report.views.len()));
}

#[test]
fn removing_points_opens_a_hole_the_metric_sees() {
    let mesh = paraboloid_cap();
    let outside_the_gap = |p: Vec3| (p.x - 0.3).powi(2) + (p.y - 0.2).powi(2) > 0.25 * 0.25;
    let report = measure(&points_of(&mesh, outside_the_gap), mesh);
    let hole_rate = report.overall.hole_rate.unwrap();
    assert!(hole_rate > 0.01, "a gap of 6% of the cap's area shows as a hole rate of {hole_rate}");
    let straight_down = &report.views[0].metrics;
    assert!(straight_down.hole_rate.unwrap() > 0.02, "{straight_down:?}");
}
