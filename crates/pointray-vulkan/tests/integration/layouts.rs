//! The ablation switches change speed, not pictures: one geometry per box renders as one
//! geometry for all, and the combined patch buffer as the hot/cold split.

use crate::common;

use common::{assert_no_validation_messages, renderer, settings, sphere_on_floor};
use pointray_scene::{BufferLayout, Frame, RenderSettings};
use pointray_vulkan::BlasLayout;

fn largest_difference(a: &Frame, b: &Frame) -> f32 {
    a.color.iter().zip(&b.color).map(|(x, y)| (*x - *y).abs().max_element()).fold(0.0, f32::max)
}

#[test]
fn blas_and_buffer_layouts_render_the_same_image() {
    let Some(renderer) = renderer() else { return };
    let scene = sphere_on_floor(0.5, 1.0);
    let split = settings(96);
    let combined = RenderSettings { buffer_layout: BufferLayout::Combined, ..split };
    let one = renderer.prepare_with_layout(&scene, BlasLayout::OneGeometry).expect("prepares");
    let per_box = renderer.prepare_with_layout(&scene, BlasLayout::GeometryPerAabb).expect("prepares");
    let reference = renderer.trace(&one, &split).expect("traces");
    for (name, frame) in [
        ("combined buffer", renderer.trace(&one, &combined).expect("traces")),
        ("geometry per box", renderer.trace(&per_box, &split).expect("traces")),
    ] {
        assert_eq!(frame.instance_id, reference.instance_id, "{name}: hit objects differ");
        assert_eq!(frame.primitive_id, reference.primitive_id, "{name}: hit patches differ");
        let difference = largest_difference(&frame, &reference);
        assert!(difference < 1e-5, "{name}: colours differ by {difference}");
    }
    assert_no_validation_messages(&renderer);
}

#[test]
fn bad_settings_are_errors_not_panics() {
    let Some(renderer) = renderer() else { return };
    let prepared = renderer.prepare(&sphere_on_floor(0.0, 1.0)).expect("prepares");
    for bad in
        [RenderSettings { width: 0, ..settings(8) }, RenderSettings { samples_per_pixel: 0, ..settings(8) }]
    {
        let error = renderer.trace(&prepared, &bad).expect_err("invalid settings must be refused");
        assert!(error.to_string().contains("invalid"), "{error}");
    }
    assert_no_validation_messages(&renderer);
}
