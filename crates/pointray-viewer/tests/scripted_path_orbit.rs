//! The path integrator in a window: the viewer opens a real window (Xvfb when there is no
//! display), renders a short scripted orbit of the demo path traced with the Vulkan backend
//! under the validation layer, straight into the swapchain, and the screenshot is the
//! path-traced image the renderer makes with the same seed, not the Whitted one. (One window
//! test a binary: an event loop may be made once per process.)

// Only some of the shared helpers are used here.
#[allow(dead_code)]
mod common;

use common::{Orbit, missing, psnr, read_png, scripted_run};
use pointray_render::{BackendChoice, BackendError};
use pointray_scene::{AovSelection, Integrator, RenderSettings, write_image};
use pointray_viewer::{ViewerError, run_viewer};

const MIN_PSNR_DB: f64 = 35.0;

#[test]
fn a_path_traced_scripted_orbit_matches_the_renderer() {
    let orbit = Orbit { frames: 3, arc_degrees: 30.0, keep_sequence: false };
    let Some(run) = scripted_run(BackendChoice::Vulkan, 4, orbit) else { return };
    let settings = RenderSettings { integrator: Integrator::Path, max_depth: 3, seed: 5, ..run.settings };
    let summary = match run_viewer(run.demo.loaded.scene.clone(), settings, run.options) {
        Ok(summary) => summary,
        Err(ViewerError::Backend(BackendError::VulkanUnavailable(error))) if error.is_no_device() => {
            return missing(&format!("no usable Vulkan device: {error}"));
        }
        Err(error) => panic!("the viewer failed: {error}"),
    };
    let renderer = pointray_test_support::vulkan_renderer().expect("the renderer opens again");
    let mut final_scene = run.demo.loaded.scene.clone();
    final_scene.camera = summary.final_camera;
    let reference = renderer.render(&final_scene, &settings).expect("the reference renders");
    assert_eq!(renderer.validation_messages(), 0, "validation messages (printed above)");
    let reference_path = run.dir.path().join("reference.png");
    write_image(&reference, &reference_path, &AovSelection::default()).expect("the reference is written");
    let whitted = renderer
        .render(&final_scene, &RenderSettings { integrator: Integrator::Whitted, ..settings })
        .expect("the Whitted image renders");
    let whitted_path = run.dir.path().join("whitted.png");
    write_image(&whitted, &whitted_path, &AovSelection::default()).expect("the Whitted image is written");
    let shot = read_png(&run.screenshot);
    let quality = psnr(&shot, &read_png(&reference_path));
    assert!(quality >= MIN_PSNR_DB, "vs the path-traced render: PSNR {quality:.2} dB < {MIN_PSNR_DB} dB");
    let against_whitted = psnr(&shot, &read_png(&whitted_path));
    assert!(against_whitted < quality - 5.0, "the window shows the Whitted image ({against_whitted:.2} dB)");
}
