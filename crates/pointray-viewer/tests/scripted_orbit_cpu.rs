//! The viewer with the CPU backend: its renderer is built once and only its camera moves
//! along the 30-frame orbit, yet the last frame is exactly the image a renderer built afresh
//! for the final camera draws. The window's presentation runs under the validation layer.

// Only some of the shared helpers are used here.
#[allow(dead_code)]
mod common;

use common::{Orbit, missing, psnr, read_png, scripted_run};
use pointray_render::BackendChoice;
use pointray_scene::{AovSelection, write_image};
use pointray_viewer::{Presentation, ViewerError, orbit_camera, run_viewer};

const FRAMES: u32 = 30;
const ARC_DEGREES: f32 = 270.0;

#[test]
fn cpu_scripted_orbit_ends_on_a_fresh_renderers_image() {
    let orbit = Orbit { frames: FRAMES, arc_degrees: ARC_DEGREES, keep_sequence: false };
    let Some(run) = scripted_run(BackendChoice::Cpu, 2, orbit) else { return };
    let (loaded, settings, dir, screenshot) = (&run.demo.loaded, run.settings, &run.dir, &run.screenshot);
    let summary = match run_viewer(loaded.scene.clone(), settings, run.options) {
        Ok(summary) => summary,
        Err(error @ ViewerError::PresentSetup(_)) => return missing(&format!("no presentation: {error}")),
        Err(error) => panic!("the viewer failed: {error}"),
    };
    assert_eq!(summary.backend, "cpu");
    assert_eq!(summary.presentation, Presentation::HostCopy, "CPU frames are in host memory");
    assert_eq!(summary.frames_presented, FRAMES as u64, "every scripted frame is presented");
    let final_camera = orbit_camera(&loaded.scene.camera, FRAMES - 1, FRAMES, ARC_DEGREES);
    assert_eq!(summary.final_camera, final_camera);

    let mut final_scene = loaded.scene.clone();
    final_scene.camera = final_camera;
    let fresh = pointray_cpu::render(&final_scene, &settings);
    let fresh_path = dir.path().join("fresh.png");
    write_image(&fresh, &fresh_path, &AovSelection::default()).expect("the fresh render is written");
    let start = pointray_cpu::render(&loaded.scene, &settings);
    let start_path = dir.path().join("start.png");
    write_image(&start, &start_path, &AovSelection::default()).expect("the first view is written");

    let shot = read_png(screenshot);
    assert!(psnr(&shot, &read_png(&start_path)) < 40.0, "the orbit changed the view");
    assert_eq!(shot, read_png(&fresh_path), "the viewer's last frame differs from a fresh render");
}
