//! Reusable trace targets: the display output is the AOV colour, encoded as a PNG would be;
//! a target follows size changes; camera and light changes need no re-preparation.

use crate::common;

use common::{assert_no_validation_messages, point_light, renderer, sphere_on_floor};
use glam::Vec3;
use pointray_kernels::srgb_encode_rgba8;
use pointray_scene::{Integrator, RenderSettings};
use pointray_test_support::largest_byte_difference;
use pointray_vulkan::{PixelOutput, TraceTarget};

fn small(width: u32, height: u32) -> RenderSettings {
    RenderSettings { width, height, ..RenderSettings::default() }
}

#[test]
fn display_output_is_the_aov_colour_in_srgb8() {
    let Some(renderer) = renderer() else { return };
    let prepared = renderer.prepare(&sphere_on_floor(0.5, 1.0)).expect("prepares");
    let settings = small(48, 32);
    let image = renderer.trace(&prepared, &settings).expect("traces");
    let mut display = TraceTarget::new(PixelOutput::Display);
    renderer.trace_into(&prepared, &settings, &mut display).expect("traces");
    let expected: Vec<u8> = image.color.iter().flat_map(|&c| srgb_encode_rgba8(c).to_le_bytes()).collect();
    let got = display.display_rgba8().expect("a display image");
    // pow() on the GPU may round the last bit differently from the CPU's powf().
    assert!(largest_byte_difference(got, &expected) <= 1, "display bytes differ from the encoded AOV colour");
    assert!(display.image().is_err(), "a display target has no AOV image");
    assert_no_validation_messages(&renderer);
}

#[test]
fn a_target_follows_size_changes() {
    let Some(renderer) = renderer() else { return };
    let prepared = renderer.prepare(&sphere_on_floor(0.5, 1.0)).expect("prepares");
    let mut target = TraceTarget::new(PixelOutput::Aovs);
    assert!(target.image().is_err(), "nothing traced yet");
    for (width, height) in [(40, 30), (40, 30), (17, 9)] {
        renderer.trace_into(&prepared, &small(width, height), &mut target).expect("traces");
        let image = target.image().expect("a image");
        assert_eq!(
            (image.width, image.height, image.color.len()),
            (width, height, (width * height) as usize)
        );
        let fresh = renderer.trace(&prepared, &small(width, height)).expect("traces");
        assert_eq!(image, fresh, "a reused target traces what a fresh one does");
    }
    assert_no_validation_messages(&renderer);
}

#[test]
fn moving_the_camera_and_the_light_matches_a_fresh_preparation() {
    let Some(renderer) = renderer() else { return };
    let mut scene = sphere_on_floor(0.5, 1.0);
    let mut prepared = renderer.prepare(&scene).expect("prepares");
    let mut target = TraceTarget::new(PixelOutput::Aovs);
    let settings = small(40, 30);
    renderer.trace_into(&prepared, &settings, &mut target).expect("traces");
    let before = target.image().expect("a image");

    scene.camera.position += Vec3::new(0.4, 0.3, 0.0);
    scene.lights =
        vec![point_light(Vec3::new(-2.0, 3.0, 1.0), 0.8), point_light(Vec3::new(2.0, 2.0, 2.0), 0.5)];
    prepared.camera = scene.camera;
    prepared.set_lights(&scene.lights).expect("sets the lights");
    renderer.trace_into(&prepared, &settings, &mut target).expect("traces");
    let moved = target.image().expect("a image");

    let fresh = renderer.trace(&renderer.prepare(&scene).expect("prepares"), &settings).expect("traces");
    assert_ne!(moved.color, before.color, "the move changed the picture");
    assert_eq!(moved, fresh, "updating in place equals preparing the moved scene");
    assert_no_validation_messages(&renderer);
}

#[test]
fn display_traces_that_continue_one_another_show_the_mean_of_all_their_samples() {
    let Some(renderer) = renderer() else { return };
    let prepared = renderer.prepare(&sphere_on_floor(0.5, 1.0)).expect("prepares");
    let path = |first_sample, samples_per_pixel| RenderSettings {
        integrator: Integrator::Path,
        max_depth: 3,
        first_sample,
        samples_per_pixel,
        ..small(40, 30)
    };
    let all_at_once = renderer.trace(&prepared, &path(0, 8)).expect("traces");
    let expected: Vec<u8> =
        all_at_once.color.iter().flat_map(|&c| srgb_encode_rgba8(c).to_le_bytes()).collect();
    let mut display = TraceTarget::new(PixelOutput::Display);
    for (first, count) in [(0, 2), (2, 2), (4, 4)] {
        renderer.trace_into(&prepared, &path(first, count), &mut display).expect("traces");
    }
    let got = display.display_rgba8().expect("a display image").to_vec();
    // Sums in another order, and pow() on the GPU, may move the last bit.
    assert!(largest_byte_difference(&got, &expected) <= 1, "the passes do not add up to one trace");
    let last_pass_alone = renderer.trace(&prepared, &path(4, 4)).expect("traces");
    let alone: Vec<u8> =
        last_pass_alone.color.iter().flat_map(|&c| srgb_encode_rgba8(c).to_le_bytes()).collect();
    assert!(largest_byte_difference(&got, &alone) > 8, "the display shows the last pass alone");
    assert_no_validation_messages(&renderer);
}
