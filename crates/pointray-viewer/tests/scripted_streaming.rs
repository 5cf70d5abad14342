//! The viewer on a GPU memory budget that the demo's point sets do not fit: a scripted orbit
//! streams their tiles frame by frame, in full or coarse, under the validation layer, and its
//! last frame is the image a scene streamed for the final camera alone draws.

mod common;

use common::{Orbit, missing, psnr, read_png, scripted_run};
use pointray_render::{BackendChoice, BackendError};
use pointray_viewer::{ViewerError, run_viewer};
use pointray_vulkan::{
    BlasLayout, DeviceOptions, DeviceSelector, PATCHES_PER_BOX_TO_FIT, SceneLayout, VulkanRenderer,
};

const FRAMES: u32 = 6;
const MIN_PSNR_DB: f64 = 35.0;

#[test]
fn a_scripted_orbit_over_the_gpu_budget_streams_tiles_and_ends_on_the_streamed_image() {
    let orbit = Orbit { frames: FRAMES, arc_degrees: 120.0, keep_sequence: true };
    let Some(mut run) = scripted_run(BackendChoice::Vulkan, 1, orbit) else { return };
    let Some(whole) = pointray_test_support::vulkan_renderer() else {
        return missing("no usable Vulkan device");
    };
    let scene = &run.demo.loaded.scene;
    // Under the demo's size in boxes of several patches, which a scene takes before it streams.
    let grouped =
        SceneLayout { blas: BlasLayout::PatchGroups(PATCHES_PER_BOX_TO_FIT), ..SceneLayout::default() };
    let whole = whole.prepare_with_layout(scene, grouped).expect("the demo prepares whole");
    let whole_bytes = whole.build_report().gpu_bytes();
    let budget = whole_bytes * 3 / 4;
    run.options.device_options = DeviceOptions { gpu_memory: Some(budget), ..DeviceOptions::VALIDATED };
    let summary = match run_viewer(scene.clone(), run.settings, run.options.clone()) {
        Ok(summary) => summary,
        Err(ViewerError::Backend(BackendError::VulkanUnavailable(error))) if error.is_no_device() => {
            return missing(&format!("no usable Vulkan device: {error}"));
        }
        Err(error) => panic!("the viewer failed: {error}"),
    };
    assert_eq!(summary.frames_presented, FRAMES as u64, "every scripted frame is presented");
    let sequence = run.sequence.as_deref().expect("the run keeps its sequence");
    let saved = std::fs::read_dir(sequence).expect("the sequence folder").count();
    assert_eq!(saved, FRAMES as usize, "one sequence image per frame");

    let options = DeviceOptions { gpu_memory: Some(budget), ..DeviceOptions::VALIDATED };
    let renderer = VulkanRenderer::new(DeviceSelector::Auto, options).expect("the renderer opens again");
    let mut final_scene = scene.clone();
    final_scene.camera = summary.final_camera;
    let size = (run.settings.width, run.settings.height);
    let layout = SceneLayout {
        stream_tiles_for: Some(size),
        coarse_tiles: true,
        ..SceneLayout::for_settings(&run.settings)
    };
    let mut streamed = renderer.prepare_with_layout(&final_scene, layout).expect("the demo streams");
    let aspect = run.settings.width as f32 / run.settings.height as f32;
    let mut stream = || streamed.stream_tiles(aspect, None).expect("streams").expect("the demo streams here");
    let residency = stream();
    eprintln!("{budget} of {whole_bytes} bytes: {residency:?}");
    assert!(residency.resident < residency.tiles, "{residency:?}: the budget holds some tiles only in full");
    assert_eq!(residency.missing(), 0, "{residency:?}: the others are drawn coarse");
    assert_eq!(
        residency.loaded,
        residency.resident + residency.coarse,
        "{residency:?}: preparing loaded the final camera's tiles"
    );
    let again = stream();
    assert!(!again.changed(), "{again:?}: nothing more to load for the same camera");
    let reference = renderer.trace(&streamed, &run.settings).expect("the reference renders");
    assert_eq!(renderer.validation_messages(), 0, "validation messages (printed above)");
    let reference_path = run.dir.path().join("reference.png");
    let aovs = pointray_scene::AovSelection::default();
    pointray_scene::write_image(&reference, &reference_path, &aovs).expect("the reference is written");
    let quality = psnr(&read_png(&run.screenshot), &read_png(&reference_path));
    eprintln!("screenshot vs the streamed render: PSNR {quality:.2} dB");
    assert!(quality >= MIN_PSNR_DB, "PSNR {quality:.2} dB < {MIN_PSNR_DB} dB");

    // The tiles of the orbit's first view, seen from its last, draw another image: the
    // viewer followed the camera.
    let mut first_tiles = renderer.prepare_with_layout(scene, layout).expect("the demo streams");
    first_tiles.camera = summary.final_camera;
    let stale = renderer.trace(&first_tiles, &run.settings).expect("the stale view renders");
    assert!(stale.color != reference.color, "the first and last views hold the same tiles");
}
