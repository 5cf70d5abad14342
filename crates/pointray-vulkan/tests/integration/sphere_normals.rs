//! An analytic sphere sampled as points: the normal AOV matches the true sphere normal.

use crate::common;

use common::{assert_no_validation_messages, primary_ray, renderer, settings, sphere_on_floor};
use pointray_scene::PatchAcceptance;

const SPHERE: u32 = 0;

fn mean_normal_error_degrees(acceptance: PatchAcceptance) -> Option<(f64, usize)> {
    let renderer = renderer()?;
    let scene = sphere_on_floor(0.0, 1.0);
    let settings = pointray_scene::RenderSettings { acceptance, ..settings(128) };
    let image = renderer.render(&scene, &settings).expect("the sphere renders");
    assert_no_validation_messages(&renderer);
    let center = glam::Vec3::Y;
    let errors: Vec<f64> = (0..image.pixel_count())
        .filter(|&i| image.instance_id[i] == SPHERE)
        .map(|i| {
            let hit = primary_ray(&scene.camera, &image, i).at(image.depth[i]);
            let truth = (hit - center).normalize();
            f64::from(image.normal[i].dot(truth).clamp(-1.0, 1.0).acos().to_degrees())
        })
        .collect();
    Some((errors.iter().sum::<f64>() / errors.len().max(1) as f64, errors.len()))
}

#[test]
fn sphere_normals_are_within_two_degrees_on_average() {
    for acceptance in [PatchAcceptance::Box, PatchAcceptance::Disk] {
        let Some((error, hits)) = mean_normal_error_degrees(acceptance) else { return };
        // The sphere covers a good part of a 128x128 view.
        assert!(hits > 2000, "only {hits} sphere pixels with {acceptance:?}");
        assert!(error < 2.0, "mean normal error {error:.3} degrees with {acceptance:?}");
        eprintln!("{acceptance:?}: {hits} sphere pixels, mean normal error {error:.3} degrees");
    }
}
