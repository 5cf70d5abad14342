//! The layout switches change speed and memory, not pictures: one geometry per box, and boxes
//! of several patches (in whole sets and in tiles), render as one box per patch in one
//! geometry, the combined patch buffer as the hot/cold split, and unpacked hot records as
//! packed ones. A scene holds only the buffers of its layout on the GPU.

use crate::common;

use common::{assert_no_validation_messages, renderer, settings, sphere_on_floor};
use pointray_kernels::{PatchCold, PatchHot};
use pointray_scene::{BufferLayout, Geometry, RenderSettings, Scene};
use pointray_test_support::{largest_color_difference, psnr_colors};
use pointray_vulkan::{BlasLayout, HotRecords, PATCHES_PER_BOX_TO_FIT, SceneLayout, VulkanError};

#[test]
fn blas_and_buffer_layouts_render_the_same_image() {
    let Some(renderer) = renderer() else { return };
    let scene = sphere_on_floor(0.5, 1.0);
    let split = settings(96);
    let combined = RenderSettings { buffer_layout: BufferLayout::Combined, ..split };
    let one = renderer.prepare(&scene).expect("prepares");
    let one_combined =
        renderer.prepare_with_layout(&scene, SceneLayout::for_settings(&combined)).expect("prepares");
    let per_box_layout = SceneLayout { blas: BlasLayout::GeometryPerAabb, ..SceneLayout::default() };
    let per_box = renderer.prepare_with_layout(&scene, per_box_layout).expect("prepares");
    let grouped = |patches_per_box, max_tile_patches| {
        let layout = SceneLayout {
            blas: BlasLayout::PatchGroups(patches_per_box),
            max_tile_patches,
            ..SceneLayout::default()
        };
        renderer.prepare_with_layout(&scene, layout).expect("prepares")
    };
    // Three a box leaves a short last box; tiles of 37 patches start boxes anew in each.
    let (fours, threes, tiled) = (grouped(4, None), grouped(3, None), grouped(4, Some(37)));
    let (one_blas, fours_blas) = (one.build_report().blas_bytes, fours.build_report().blas_bytes);
    assert!(fours_blas < one_blas / 2, "boxes of 4 patches take {fours_blas} bytes against {one_blas}");
    let reference = renderer.trace(&one, &split).expect("traces");
    for (name, image) in [
        ("combined buffer", renderer.trace(&one_combined, &combined).expect("traces")),
        ("geometry per box", renderer.trace(&per_box, &split).expect("traces")),
        ("4 patches a box", renderer.trace(&fours, &split).expect("traces")),
        ("3 patches a box", renderer.trace(&threes, &split).expect("traces")),
        ("4 patches a box in tiles of 37", renderer.trace(&tiled, &split).expect("traces")),
    ] {
        assert_eq!(image.instance_id, reference.instance_id, "{name}: hit objects differ");
        assert_eq!(image.primitive_id, reference.primitive_id, "{name}: hit patches differ");
        let difference = largest_color_difference(&image, &reference);
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

/// The bytes of every buffer a trace of `scene` reads, besides the patch records: the meshes'
/// vertices (vec4) and indices.
fn mesh_bytes(scene: &Scene) -> u64 {
    let bytes = |geometry: &Geometry| match geometry {
        Geometry::Mesh(mesh) => mesh.positions.len() * 16 + mesh.triangles.len() * 12,
        Geometry::Patches(_) => 0,
    };
    scene.objects.iter().map(|object| bytes(&object.geometry) as u64).sum()
}

#[test]
fn only_the_traced_layout_stays_on_the_gpu() {
    let Some(renderer) = renderer() else { return };
    let scene = sphere_on_floor(0.5, 1.0);
    let patches = patch_count(&scene);
    assert!(patches > 0);
    let hot_and_cold = (size_of::<PatchHot>() + size_of::<PatchCold>()) as u64;
    let split = renderer.prepare(&scene).expect("prepares").build_report();
    let hot = size_of::<PatchHot>() as u64;
    assert_eq!(
        split.geometry_bytes,
        patches * hot + mesh_bytes(&scene),
        "no boxes, no combined records, and no cold ones where no material colours hits by the points"
    );
    let mut coloured = scene.clone();
    coloured.objects.iter_mut().for_each(|object| object.material.use_point_colors = true);
    let split = renderer.prepare(&coloured).expect("prepares").build_report();
    assert_eq!(split.geometry_bytes, patches * hot_and_cold + mesh_bytes(&scene), "hot and cold records");
    let combined = SceneLayout { buffers: BufferLayout::Combined, ..SceneLayout::default() };
    let report = renderer.prepare_with_layout(&scene, combined).expect("prepares").build_report();
    // std430 aligns the combined record to its largest member's alignment, 4 bytes: no padding.
    assert_eq!(report.geometry_bytes, patches * hot_and_cold + mesh_bytes(&scene), "combined records only");
    assert_eq!(report.gpu_bytes(), report.geometry_bytes + report.blas_bytes + report.tlas_bytes);
    assert_no_validation_messages(&renderer);
}

#[test]
fn tracing_buffers_the_scene_lacks_is_an_error() {
    let Some(renderer) = renderer() else { return };
    let prepared = renderer.prepare(&sphere_on_floor(0.0, 1.0)).expect("prepares");
    let combined = RenderSettings { buffer_layout: BufferLayout::Combined, ..settings(8) };
    let error = renderer.trace(&prepared, &combined).expect_err("the combined buffer was not uploaded");
    assert!(error.to_string().contains("prepared with the split hot and cold ones only"), "{error}");
    assert!(renderer.render(&sphere_on_floor(0.0, 1.0), &combined).is_ok(), "render prepares what it traces");
    assert_no_validation_messages(&renderer);
}

#[test]
fn a_scene_over_its_budget_in_boxes_of_one_is_grouped_to_fit() {
    let Some(renderer) = renderer() else { return };
    let scene = sphere_on_floor(0.5, 1.0);
    // Packed records throughout: unpacking to fit has a test of its own.
    let open = SceneLayout { unpack_to_fit: false, ..SceneLayout::for_settings(&settings(96)) };
    assert!(open.group_to_fit, "settings that leave the patches a box open group to fit");
    let ones = renderer.prepare_with_layout(&scene, open).expect("prepares").build_report();
    assert_eq!(ones.patches_per_box, 1, "a scene that fits keeps a box per patch");
    let grouped =
        SceneLayout { blas: BlasLayout::PatchGroups(PATCHES_PER_BOX_TO_FIT), ..SceneLayout::default() };
    let fours = renderer.prepare_with_layout(&scene, grouped).expect("prepares");
    // Between what each layout keeps: smaller tiles cannot bring boxes of one under it.
    let fours_need = fours.build_report().peak_build_bytes.max(fours.build_report().gpu_bytes());
    let budget = Some((ones.gpu_bytes() + fours_need) / 2);
    let fixed = SceneLayout { memory_budget: budget, group_to_fit: false, ..open };
    let refused = renderer.prepare_with_layout(&scene, fixed).err();
    assert!(matches!(refused, Some(VulkanError::OverBudget(_))), "boxes of one do not fit: {refused:?}");
    let fitted =
        renderer.prepare_with_layout(&scene, SceneLayout { memory_budget: budget, ..open }).expect("fits");
    assert_eq!(fitted.build_report().patches_per_box, PATCHES_PER_BOX_TO_FIT);
    let (image, reference) = (renderer.trace(&fitted, &settings(96)), renderer.trace(&fours, &settings(96)));
    let (image, reference) = (image.expect("traces"), reference.expect("traces"));
    assert_eq!(image.primitive_id, reference.primitive_id, "grouped to fit, the scene renders as grouped");
    assert_no_validation_messages(&renderer);
}

#[test]
fn unpacked_hot_records_render_as_packed_ones_and_are_taken_where_they_fit() {
    let Some(renderer) = renderer() else { return };
    let scene = sphere_on_floor(0.5, 1.0);
    let open = SceneLayout::for_settings(&settings(96));
    assert!(open.unpack_to_fit, "split buffers in boxes of one unpack to fit");
    let unpacked = renderer.prepare_with_layout(&scene, open).expect("prepares");
    let packed_layout = SceneLayout { unpack_to_fit: false, ..open };
    let packed = renderer.prepare_with_layout(&scene, packed_layout).expect("prepares");
    let (unpacked_report, packed_report) = (unpacked.build_report(), packed.build_report());
    assert_eq!(unpacked_report.hot_records, HotRecords::Unpacked);
    assert_eq!(packed_report.hot_records, HotRecords::Packed);
    let patches = patch_count(&scene);
    let extra =
        patches * (HotRecords::Unpacked.bytes_per_patch() - HotRecords::Packed.bytes_per_patch()) as u64;
    assert_eq!(unpacked_report.geometry_bytes, packed_report.geometry_bytes + extra);
    // The unpacked frame is the packed one decoded on the host, whose sine and cosine round
    // otherwise than the device's: the same picture, but where two overlapping patches all but
    // tie, a pixel may take the other.
    let reference = renderer.trace(&packed, &settings(96)).expect("traces");
    let image = renderer.trace(&unpacked, &settings(96)).expect("traces");
    assert_eq!(image.instance_id, reference.instance_id, "hit objects differ");
    let psnr = psnr_colors(&image, &reference);
    assert!(psnr >= 50.0, "{psnr:.1} dB against packed records");
    let moved = image.primitive_id.iter().zip(&reference.primitive_id).filter(|(a, b)| a != b).count();
    assert!(moved * 100 <= image.primitive_id.len(), "{moved} pixels hit another patch");
    // A budget between the two: the scene keeps boxes of one, with packed records. In small
    // tiles, so that the records, not one large build, make each layout's peak.
    let tiled = SceneLayout { max_tile_patches: Some(64), ..open };
    let need = |layout| {
        let report = renderer.prepare_with_layout(&scene, layout).expect("prepares").build_report();
        report.peak_build_bytes.max(report.gpu_bytes())
    };
    let (unpacked_need, packed_need) = (need(tiled), need(SceneLayout { unpack_to_fit: false, ..tiled }));
    assert!(unpacked_need > packed_need, "{unpacked_need} against {packed_need} bytes");
    let budget = Some((unpacked_need + packed_need) / 2);
    let fitted = renderer
        .prepare_with_layout(&scene, SceneLayout { memory_budget: budget, ..tiled })
        .expect("fits packed")
        .build_report();
    assert_eq!((fitted.hot_records, fitted.patches_per_box), (HotRecords::Packed, 1));
    assert_eq!(fitted.geometry_bytes, packed_report.geometry_bytes);
    assert_no_validation_messages(&renderer);
}

fn patch_count(scene: &Scene) -> u64 {
    let count = |geometry: &Geometry| match geometry {
        Geometry::Patches(set) => set.len() as u64,
        Geometry::Mesh(_) => 0,
    };
    scene.objects.iter().map(|object| count(&object.geometry)).sum()
}
