//! The viewer opens a real window (Xvfb when there is no display), renders a 30-frame
//! scripted orbit of the procedural demo with the Vulkan backend (lavapipe here) under the
//! validation layer, tracing straight into the swapchain on the renderer's device, saves a
//! screenshot (read back from the display buffer), and the screenshot is the image the
//! renderers make from the final camera.

mod common;

use common::{Orbit, missing, psnr, read_png, scripted_run};
use pointray_render::{BackendChoice, BackendError};
use pointray_scene::{AovSelection, RenderedImage, write_image};
use pointray_viewer::{Presentation, ViewerError, orbit_camera, run_viewer};

const FRAMES: u32 = 30;
const ARC_DEGREES: f32 = 360.0;
const MIN_PSNR_DB: f64 = 35.0;

fn covered_objects(frame: &RenderedImage) -> usize {
    let mut ids: Vec<u32> =
        frame.instance_id.iter().copied().filter(|&id| id != RenderedImage::MISS).collect();
    ids.sort_unstable();
    ids.dedup();
    ids.len()
}

#[test]
fn scripted_orbit_screenshot_matches_the_renderer() {
    let orbit = Orbit { frames: FRAMES, arc_degrees: ARC_DEGREES, keep_sequence: true };
    let Some(run) = scripted_run(BackendChoice::Vulkan, 1, orbit) else { return };
    let (loaded, settings, dir, screenshot) = (&run.demo.loaded, run.settings, &run.dir, &run.screenshot);
    let sequence = run.sequence.as_deref().expect("the run keeps its sequence");
    let summary = match run_viewer(loaded.scene.clone(), settings, run.options) {
        Ok(summary) => summary,
        Err(ViewerError::Backend(BackendError::VulkanUnavailable(error))) if error.is_no_device() => {
            return missing(&format!("no usable Vulkan device: {error}"));
        }
        Err(error) => panic!("the viewer failed: {error}"),
    };
    assert_eq!(summary.presentation, Presentation::Direct, "Vulkan frames skip the host");
    assert_eq!(summary.frames_presented, FRAMES as u64, "every scripted frame is presented");
    let expected_camera = orbit_camera(&loaded.scene.camera, FRAMES - 1, FRAMES, ARC_DEGREES);
    assert_eq!(summary.final_camera, expected_camera);
    assert!(expected_camera.position.distance(loaded.scene.camera.position) > 1e-3, "the orbit moved");

    // `pointray render` with the final camera: the same scene, settings and camera.
    let renderer = pointray_test_support::vulkan_renderer().expect("the renderer opens again");
    let mut final_scene = loaded.scene.clone();
    final_scene.camera = summary.final_camera;
    let reference = renderer.render(&final_scene, &settings).expect("the reference renders");
    assert_eq!(renderer.validation_messages(), 0, "validation messages (printed above)");
    assert!(covered_objects(&reference) >= 2, "the reference view shows the demo's objects");
    let reference_path = dir.path().join("reference.png");
    write_image(&reference, &reference_path, &AovSelection::default()).expect("the reference is written");

    // `pointray render --backend auto` picks the CPU renderer on CPU Vulkan drivers: the
    // screenshot must match it too.
    let cpu_reference = pointray_cpu::render(&final_scene, &settings);
    let cpu_path = dir.path().join("cpu.png");
    write_image(&cpu_reference, &cpu_path, &AovSelection::default()).expect("the CPU reference is written");

    let shot = read_png(screenshot);
    // Every frame was read back for the sequence; the last is the screenshot.
    let saved = std::fs::read_dir(sequence).expect("the sequence folder").count();
    assert_eq!(saved, FRAMES as usize, "one sequence image per frame");
    let last = read_png(&sequence.join(format!("frame-{:05}.png", FRAMES - 1)));
    assert!(last == shot, "the last sequence frame differs from the screenshot");
    for (name, path) in [("vulkan", &reference_path), ("cpu", &cpu_path)] {
        let quality = psnr(&shot, &read_png(path));
        eprintln!("screenshot vs {name} render: PSNR {quality:.2} dB");
        assert!(quality >= MIN_PSNR_DB, "vs {name}: PSNR {quality:.2} dB < {MIN_PSNR_DB} dB");
    }
}
