//! What the benchmark relies on: exact GPU ray and intersection-call counts, per-frame
//! timestamps of the frame loop, and the build report of a prepared scene.

use crate::common;

use common::{assert_no_validation_messages, object, patches, renderer, sphere_on_floor};
use glam::Vec3;
use pointray_kernels::PatchHot;
use pointray_scene::{Background, Camera, Material, RenderSettings, Scene};
use pointray_test_support::analytic_scenes::patch_set;
use pointray_vulkan::PixelOutput;

fn small(width: u32, height: u32) -> RenderSettings {
    RenderSettings { width, height, ..RenderSettings::default() }
}

#[test]
fn primary_rays_only_count_one_per_sample() {
    let Some(renderer) = renderer() else { return };
    let prepared = renderer.prepare(&sphere_on_floor(0.5, 1.0)).expect("prepares");
    let settings = RenderSettings { max_depth: 1, shadows: false, samples_per_pixel: 3, ..small(24, 16) };
    assert_eq!(renderer.count_rays(&prepared, &settings).expect("counts").rays, 24 * 16 * 3);
    assert_no_validation_messages(&renderer);
}

#[test]
fn shadows_and_reflections_add_rays_within_their_bounds() {
    let Some(renderer) = renderer() else { return };
    let scene = sphere_on_floor(0.5, 1.0);
    let prepared = renderer.prepare(&scene).expect("prepares");
    let settings = small(32, 32);
    let rays = renderer.count_rays(&prepared, &settings).expect("counts").rays;
    let primary = 32 * 32;
    // Every pixel sees the sphere or the reflective floor, so some shadow and mirror rays are
    // traced; at most one shadow ray per light and one mirror ray per segment.
    let most = primary * u64::from(settings.max_depth) * (1 + scene.lights.len() as u64);
    assert!(rays > primary && rays <= most, "{rays} rays, expected in ({primary}, {most}]");
    assert_no_validation_messages(&renderer);
}

/// One flat disk of radius 1 in the plane z = 0, boxed by the cube [-1, 1]³, seen from
/// (0, 0, 1.5) along `look`, with no lights.
fn one_patch_looking(look: Vec3) -> Scene {
    let disk = PatchHot::isotropic(Vec3::ZERO, Vec3::X, Vec3::Z, [0.0; 6], 1.0);
    let position = Vec3::new(0.0, 0.0, 1.5);
    let camera = Camera { position, look_at: position + look, up: Vec3::Y, vertical_fov_degrees: 40.0 };
    let disk = object("disk", patches(patch_set(vec![disk])), Material::default());
    Scene { camera, lights: Vec::new(), background: Background::Solid(Vec3::ZERO), objects: vec![disk] }
}

#[test]
fn every_ray_into_the_one_box_calls_the_intersection_shader_once() {
    let Some(renderer) = renderer() else { return };
    let settings = RenderSettings { max_depth: 1, shadows: false, ..small(24, 16) };
    // Looking at the disk, the view lies within its box: every primary ray enters the box,
    // and the traversal has one box to report to it.
    let prepared = renderer.prepare(&one_patch_looking(Vec3::NEG_Z)).expect("prepares");
    let counts = renderer.count_rays(&prepared, &settings).expect("counts");
    assert_eq!((counts.rays, counts.intersection_calls), (24 * 16, 24 * 16));
    assert_eq!(counts.intersection_calls_per_ray(), 1.0);
    // Looking away, every ray misses the box, so the intersection shader is never called.
    let prepared = renderer.prepare(&one_patch_looking(Vec3::Z)).expect("prepares");
    let counts = renderer.count_rays(&prepared, &settings).expect("counts");
    assert_eq!((counts.rays, counts.intersection_calls), (24 * 16, 0));
    assert_no_validation_messages(&renderer);
}

#[test]
fn shadow_rays_call_the_intersection_shader_too() {
    let Some(renderer) = renderer() else { return };
    let prepared = renderer.prepare(&sphere_on_floor(0.0, 1.0)).expect("prepares");
    let primary_only = RenderSettings { max_depth: 1, shadows: false, ..small(32, 32) };
    let primary = renderer.count_rays(&prepared, &primary_only).expect("counts");
    let shadowed =
        renderer.count_rays(&prepared, &RenderSettings { shadows: true, ..primary_only }).expect("counts");
    assert!(primary.intersection_calls > 0, "{primary:?}");
    assert!(
        shadowed.rays > primary.rays && shadowed.intersection_calls > primary.intersection_calls,
        "{shadowed:?}"
    );
    assert_no_validation_messages(&renderer);
}

#[test]
fn frame_loop_times_every_frame() {
    let Some(renderer) = renderer() else { return };
    let prepared = renderer.prepare(&sphere_on_floor(0.5, 1.0)).expect("prepares");
    let times = renderer.trace_frames(&prepared, &small(32, 24), 4, PixelOutput::Display).expect("traces");
    assert_eq!((times.trace.len(), times.frame.len()), (4, 4));
    for (trace, frame) in times.trace.iter().zip(&times.frame) {
        assert!(!trace.is_zero() && frame >= trace, "trace {trace:?}, whole frame {frame:?}");
    }
    assert!(times.wall >= times.frame.iter().sum(), "the wall time covers the GPU time");
    assert!(
        renderer.trace_frames(&prepared, &small(8, 8), 0, PixelOutput::Aovs).is_err(),
        "zero frames is an error"
    );
    assert_no_validation_messages(&renderer);
}

#[test]
fn build_report_counts_every_structure() {
    let Some(renderer) = renderer() else { return };
    let scene = sphere_on_floor(0.5, 1.0);
    let report = renderer.prepare(&scene).expect("prepares").build_report();
    assert_eq!(report.blas_count, scene.objects.len());
    assert!(report.blas_bytes > 0 && report.tlas_bytes > 0 && report.geometry_bytes > 0, "{report:?}");
    assert!(!report.blas_build.is_zero() && !report.tlas_build.is_zero(), "{report:?}");
}
