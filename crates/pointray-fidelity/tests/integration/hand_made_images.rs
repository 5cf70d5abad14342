//! The metrics on tiny images whose answers are worked out by hand.

use glam::Vec3;
use pointray_fidelity::{FidelityError, PixelComparison};
use pointray_scene::RenderedImage;

/// A hit: depth, normal, colour.
type Hit = (f32, Vec3, Vec3);

/// One row of pixels; `None` is a miss (black, infinite depth, zero normal).
fn image(pixels: &[(Option<Hit>, Vec3)]) -> RenderedImage {
    RenderedImage {
        width: pixels.len() as u32,
        height: 1,
        color: pixels.iter().map(|(hit, background)| hit.map_or(*background, |h| h.2)).collect(),
        depth: pixels.iter().map(|(hit, _)| hit.map_or(f32::INFINITY, |h| h.0)).collect(),
        normal: pixels.iter().map(|(hit, _)| hit.map_or(Vec3::ZERO, |h| h.1)).collect(),
        instance_id: pixels
            .iter()
            .map(|(hit, _)| if hit.is_some() { 0 } else { RenderedImage::MISS })
            .collect(),
        primitive_id: pixels
            .iter()
            .map(|(hit, _)| if hit.is_some() { 7 } else { RenderedImage::MISS })
            .collect(),
        albedo: None,
    }
}

const GREY: Vec3 = Vec3::splat(0.5);

/// Five pixels: both hit (depth off by 0.1, same normal, colour off by 0.1 in red), both hit
/// (same depth, normal flipped and tilted by 60°), a hole, a false surface, both miss (with
/// over-bright backgrounds that clamp to the same value). Other misses show black.
fn mesh_and_points() -> (RenderedImage, RenderedImage) {
    let tilted_and_flipped = -Vec3::new(60f32.to_radians().sin(), 0.0, 60f32.to_radians().cos());
    let mesh = image(&[
        (Some((1.0, Vec3::Z, GREY)), Vec3::ZERO),
        (Some((2.0, Vec3::Z, GREY)), Vec3::ZERO),
        (Some((3.0, Vec3::Z, GREY)), Vec3::ZERO),
        (None, Vec3::ZERO),
        (None, Vec3::splat(2.0)),
    ]);
    let points = image(&[
        (Some((1.1, Vec3::Z, GREY + Vec3::new(0.1, 0.0, 0.0))), Vec3::ZERO),
        (Some((2.0, tilted_and_flipped, GREY)), Vec3::ZERO),
        (None, Vec3::ZERO),
        (Some((4.0, Vec3::Z, GREY)), Vec3::ZERO),
        (None, Vec3::splat(1.5)),
    ]);
    (mesh, points)
}

fn close(actual: Option<f64>, expected: f64, tolerance: f64) -> bool {
    actual.is_some_and(|a| (a - expected).abs() <= tolerance)
}

#[test]
fn rates_errors_and_psnr_match_the_hand_computed_values() {
    let (mesh, points) = mesh_and_points();
    let metrics = PixelComparison::of_images(&mesh, &points, 2.0).unwrap().metrics();
    assert_eq!(metrics.mesh_pixels, 3);
    assert_eq!(metrics.both_hit_pixels, 2);
    assert!(close(metrics.hole_rate, 1.0 / 3.0, 1e-12), "{metrics:?}");
    // One row: the hole's neighbours above and below lie off the image, so it is no pinhole.
    assert_eq!(metrics.pinhole_rate, Some(0.0));
    assert!(close(metrics.false_surface_rate, 1.0 / 3.0, 1e-12), "{metrics:?}");
    // Depth errors 0.1 / 2 and 0.
    assert!(close(metrics.depth_error_mean, 0.025, 1e-6), "{metrics:?}");
    assert!(close(metrics.depth_error_p99, 0.05, 1e-6), "{metrics:?}");
    // Normal errors 0° and 60° (the flip does not count).
    assert!(close(metrics.normal_error_mean_degrees, 30.0, 1e-3), "{metrics:?}");
    assert!(close(metrics.normal_error_p95_degrees, 60.0, 1e-3), "{metrics:?}");
    // Squared error: 0.1² (pixel 0) + 3 * 0.5² (hole: grey against black) + 3 * 0.5² (false
    // surface), over 5 pixels * 3 channels.
    let mean_squared_error = (0.01 + 6.0 * 0.25) / 15.0;
    assert!(close(metrics.psnr_db, -10.0 * f64::log10(mean_squared_error), 1e-4), "{metrics:?}");
}

#[test]
fn identical_images_have_no_holes_no_errors_and_infinite_psnr() {
    let (mesh, _) = mesh_and_points();
    let metrics = PixelComparison::of_images(&mesh, &mesh, 1.0).unwrap().metrics();
    assert_eq!(metrics.hole_rate, Some(0.0));
    assert_eq!(metrics.false_surface_rate, Some(0.0));
    assert_eq!(metrics.depth_error_p99, Some(0.0));
    assert_eq!(metrics.normal_error_p95_degrees, Some(0.0));
    assert_eq!(metrics.psnr_db, None);
}

#[test]
fn an_empty_mesh_image_has_no_rates() {
    let empty = image(&[(None, GREY), (None, GREY)]);
    let metrics = PixelComparison::of_images(&empty, &empty, 1.0).unwrap().metrics();
    assert_eq!((metrics.hole_rate, metrics.depth_error_mean), (None, None));
}

#[test]
fn merging_pools_pixels_rather_than_averaging_rates() {
    let (mesh, points) = mesh_and_points();
    let mut pooled = PixelComparison::of_images(&mesh, &points, 2.0).unwrap();
    // A second view of nine mesh pixels and no hole: pooled, 1 hole in 12 mesh pixels (the
    // mean of the two views' rates would be 1/6).
    let full = image(&[(Some((1.0, Vec3::Z, GREY)), Vec3::ZERO); 9]);
    pooled.merge(PixelComparison::of_images(&full, &full, 2.0).unwrap());
    let metrics = pooled.metrics();
    assert_eq!(metrics.mesh_pixels, 12);
    assert!(close(metrics.hole_rate, 1.0 / 12.0, 1e-12), "{metrics:?}");
    assert_eq!(metrics.both_hit_pixels, 11);
}

#[test]
fn only_holes_the_mesh_surrounds_are_pinholes() {
    let hit = (Some((1.0, Vec3::Z, GREY)), Vec3::ZERO);
    let square = |holes: &[usize]| {
        let pixels: Vec<_> =
            (0..25).map(|i| if holes.contains(&i) { (None, Vec3::ZERO) } else { hit }).collect();
        RenderedImage { width: 5, height: 5, ..image(&pixels) }
    };
    // The mesh misses its corner pixel 0; the points miss the centre (12, surrounded),
    // pixel 6 (beside the missing corner) and pixel 10 (on the image's left edge).
    let metrics = PixelComparison::of_images(&square(&[0]), &square(&[0, 6, 10, 12]), 1.0).unwrap().metrics();
    assert_eq!(metrics.mesh_pixels, 24);
    assert!(close(metrics.hole_rate, 3.0 / 24.0, 1e-12), "{metrics:?}");
    assert!(close(metrics.pinhole_rate, 1.0 / 24.0, 1e-12), "{metrics:?}");
}

#[test]
fn images_of_different_sizes_are_an_error() {
    let (mesh, _) = mesh_and_points();
    let small = image(&[(None, GREY)]);
    let result = PixelComparison::of_images(&mesh, &small, 1.0);
    assert!(matches!(result, Err(FidelityError::ImageSizeMismatch { mesh_width: 5, points_width: 1, .. })));
}
