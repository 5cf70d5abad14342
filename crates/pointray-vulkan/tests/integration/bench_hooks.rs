//! What the benchmark relies on: exact GPU ray counts, per-frame timestamps of the frame
//! loop, and the build report of a prepared scene.

use crate::common;

use common::{assert_no_validation_messages, renderer, sphere_on_floor};
use pointray_scene::RenderSettings;
use pointray_vulkan::PixelOutput;

fn small(width: u32, height: u32) -> RenderSettings {
    RenderSettings { width, height, ..RenderSettings::default() }
}

#[test]
fn primary_rays_only_count_one_per_sample() {
    let Some(renderer) = renderer() else { return };
    let prepared = renderer.prepare(&sphere_on_floor(0.5, 1.0)).expect("prepares");
    let settings = RenderSettings { max_depth: 1, shadows: false, samples_per_pixel: 3, ..small(24, 16) };
    assert_eq!(renderer.count_rays(&prepared, &settings).expect("counts"), 24 * 16 * 3);
    assert_no_validation_messages(&renderer);
}

#[test]
fn shadows_and_reflections_add_rays_within_their_bounds() {
    let Some(renderer) = renderer() else { return };
    let scene = sphere_on_floor(0.5, 1.0);
    let prepared = renderer.prepare(&scene).expect("prepares");
    let settings = small(32, 32);
    let rays = renderer.count_rays(&prepared, &settings).expect("counts");
    let primary = 32 * 32;
    // Every pixel sees the sphere or the reflective floor, so some shadow and mirror rays are
    // traced; at most one shadow ray per light and one mirror ray per segment.
    let most = primary * u64::from(settings.max_depth) * (1 + scene.lights.len() as u64);
    assert!(rays > primary && rays <= most, "{rays} rays, expected in ({primary}, {most}]");
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
