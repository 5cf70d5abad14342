//! Point sets in tiles: one BLAS per run of patches, instances in one TLAS. A cloud forced
//! into many small tiles draws exactly the image it draws whole, on the GPU and on the CPU,
//! and the two backends agree; a scene over its GPU memory budget is refused before upload.

use super::against_cpu::assert_images_agree;
use super::point_colors::{coloured_sphere, lit_on_floor};

use glam::Vec3;
use pointray_cpu::CpuRenderer;
use pointray_kernels::Aabb;
use pointray_scene::{Geometry, Material, RenderedImage, Scene, SceneObject};
use pointray_test_support::floor_scenes::{model_on_floor, settings, sphere_on_floor};
use pointray_test_support::{assert_no_validation_messages, prepped_points, vulkan_renderer};
use pointray_vulkan::{DeviceOptions, DeviceSelector, SceneLayout, VulkanError, VulkanRenderer};

/// Small enough that every point set here splits into dozens of tiles, and not a divisor of
/// their sizes, so that tiles differ in length.
const SMALL_TILE: u32 = 97;

/// The prepped bunny, and its bounds in the world.
pub(crate) fn bunny_object(path: &std::path::Path) -> (SceneObject, Aabb) {
    let bunny = prepped_points("bunny", path, Material { reflectivity: 0.0, ..Material::default() });
    let Geometry::Patches(patches) = &bunny.geometry else { unreachable!("prepped points are patches") };
    let bounds = patches.bounds().expect("the bunny has patches");
    let offset = patches.offset.as_vec3();
    let world = Aabb::new(Vec3::from(bounds.min) + offset, Vec3::from(bounds.max) + offset);
    (bunny, world)
}

fn bunny_on_floor(path: &std::path::Path) -> Scene {
    let (bunny, world) = bunny_object(path);
    model_on_floor(bunny, world, 0.4)
}

pub(crate) fn patch_count(scene: &Scene) -> usize {
    let count = |geometry: &Geometry| match geometry {
        Geometry::Patches(set) => set.len(),
        Geometry::Mesh(_) => 0,
    };
    scene.objects.iter().map(|object| count(&object.geometry)).sum()
}

/// The same hits: every pixel meets the same object at the bit-identical depth, and where it
/// meets the same patch everything about it is identical. Overlapping patches can tie at
/// one depth (on the prepped sphere, where every neighbourhood fits the same surface, a
/// pixel in twenty does; the backends disagree on those as much): the renderer keeps
/// whichever its traversal reports first, tiled or not, so there the image may differ
/// only by what separates two patches through the same point.
pub(crate) fn assert_same_hits(name: &str, tiled: &RenderedImage, whole: &RenderedImage) {
    let pixels = whole.pixel_count();
    let same_nearest = |i: usize| {
        tiled.instance_id[i] == whole.instance_id[i] && tiled.depth[i].to_bits() == whole.depth[i].to_bits()
    };
    let identical = |i: usize| {
        tiled.primitive_id[i] == whole.primitive_id[i]
            && tiled.normal[i] == whole.normal[i]
            && tiled.color[i] == whole.color[i]
    };
    let show = |i: usize| {
        format!(
            "pixel {i}: tiled {}/{} at {}, whole {}/{} at {}",
            tiled.instance_id[i],
            tiled.primitive_id[i],
            tiled.depth[i],
            whole.instance_id[i],
            whole.primitive_id[i],
            whole.depth[i]
        )
    };
    let moved: Vec<String> = (0..pixels).filter(|&i| !same_nearest(i)).take(5).map(show).collect();
    assert!(moved.is_empty(), "{name}: nearest hits differ: {moved:#?}");
    let same_patch_differs: Vec<String> = (0..pixels)
        .filter(|&i| tiled.primitive_id[i] == whole.primitive_id[i] && !identical(i))
        .take(5)
        .map(show)
        .collect();
    assert!(
        same_patch_differs.is_empty(),
        "{name}: the same hit shades differently: {same_patch_differs:#?}"
    );
    let ties = (0..pixels).filter(|&i| tiled.primitive_id[i] != whole.primitive_id[i]).count();
    let psnr = tiled.color_psnr(whole);
    eprintln!("{name}: {ties} of {pixels} pixels hit another patch at the same depth; {psnr:.1} dB");
    assert!(psnr >= 50.0, "{name}: the tiled image differs from the whole one: {psnr:.1} dB");
}

#[test]
fn a_cloud_in_many_tiles_draws_the_untiled_image() {
    let Some(renderer) = vulkan_renderer() else { return };
    let bunny = pointray_test_support::data_file("points/bunny.ply");
    // Prepped clouds: the patches of an exact sphere (`sphere_on_floor`) tie at equal depths,
    // which either backend may break either way.
    let scenes = [
        ("bunny over a mirror floor", bunny_on_floor(&bunny)),
        ("lit coloured sphere", lit_on_floor(coloured_sphere())),
    ];
    for (name, scene) in scenes {
        let settings = settings(128);
        let whole = renderer.prepare(&scene).expect("prepares whole");
        let tiled_layout = SceneLayout { max_tile_patches: Some(SMALL_TILE), ..SceneLayout::default() };
        let tiled = renderer.prepare_with_layout(&scene, tiled_layout).expect("prepares in tiles");
        let tiles = patch_count(&scene).div_ceil(SMALL_TILE as usize);
        assert!(tiles >= 40, "{name}: {tiles} tiles");
        // One BLAS per tile of the sphere, and the floor's.
        assert_eq!(tiled.build_report().blas_count, tiles + 1, "{name}");
        assert_eq!(whole.build_report().blas_count, 2, "{name}");
        let whole_image = renderer.trace(&whole, &settings).expect("traces whole");
        let tiled_image = renderer.trace(&tiled, &settings).expect("traces in tiles");
        assert!(
            tiled_image.hit_mask().iter().filter(|&&hit| hit).count() > 128 * 128 / 4,
            "{name}: the view is filled"
        );
        assert_same_hits(&format!("{name}, GPU"), &tiled_image, &whole_image);
        let cpu = CpuRenderer::with_max_tile_patches(&scene, SMALL_TILE as usize);
        assert_eq!(cpu.tile_count(), tiles + 1, "{name}: the CPU's tiles");
        assert_images_agree(&format!("{name} in tiles"), &cpu.render(&settings), &tiled_image);
    }
    assert_no_validation_messages(&renderer);
}

#[test]
fn a_scene_over_its_gpu_budget_is_refused_with_the_numbers() {
    let Some(renderer) = vulkan_renderer() else { return };
    let scene = sphere_on_floor(0.5, 1.0);
    let budget = 64 * 1024;
    let layout = SceneLayout { memory_budget: Some(budget), ..SceneLayout::default() };
    let error = renderer.prepare_with_layout(&scene, layout).err().expect("64 KiB holds no 6,000 patches");
    assert!(matches!(error, VulkanError::OverBudget(_)), "{error:?}");
    let message = error.to_string();
    assert!(message.contains("over the GPU memory budget of 0.1 MiB"), "{message}");
    assert!(message.contains("the scene needs") && message.contains("acceleration structures"), "{message}");
    let prepared = renderer.prepare(&scene).expect("prepares without a budget");
    let used = prepared.build_report().gpu_bytes();
    let roomy = SceneLayout { memory_budget: Some(4 * used + (1 << 20)), ..SceneLayout::default() };
    assert!(renderer.prepare_with_layout(&scene, roomy).is_ok(), "a budget with room prepares");
    assert_no_validation_messages(&renderer);
}

#[test]
fn a_budget_below_one_build_splits_the_cloud_into_tiles_that_fit() {
    let Some(renderer) = vulkan_renderer() else { return };
    let bunny = pointray_test_support::data_file("points/bunny.ply");
    let scene = bunny_on_floor(&bunny);
    let settings = settings(128);
    let whole = renderer.prepare(&scene).expect("prepares whole");
    let report = whole.build_report();
    assert_eq!(report.blas_count, 2, "the bunny and the floor");
    // Room for the finished scene and a little more, but not for the bunny's build in one piece.
    let budget = report.gpu_bytes() + report.gpu_bytes() / 4;
    assert!(report.peak_build_bytes > budget, "{report:?}: the whole build must not fit {budget}");
    let layout = SceneLayout { memory_budget: Some(budget), ..SceneLayout::default() };
    let fitted = renderer.prepare_with_layout(&scene, layout).expect("prepares within the budget");
    let fitted_report = fitted.build_report();
    eprintln!("whole: {report:?}\nfitted to {budget}: {fitted_report:?}");
    assert!(fitted_report.blas_count > 2, "{fitted_report:?}");
    assert!(fitted_report.peak_build_bytes <= budget, "{fitted_report:?} over {budget}");
    let whole_image = renderer.trace(&whole, &settings).expect("traces whole");
    let fitted_image = renderer.trace(&fitted, &settings).expect("traces in tiles");
    assert_same_hits("bunny fitted to a budget", &fitted_image, &whole_image);
    assert_no_validation_messages(&renderer);
}

#[test]
fn a_device_gpu_memory_option_budgets_every_scene_unless_a_layout_names_one() {
    let Some(renderer) = vulkan_renderer() else { return };
    let scene = sphere_on_floor(0.5, 1.0);
    let used = renderer.prepare(&scene).expect("prepares without a budget").build_report().gpu_bytes();
    let options = DeviceOptions { gpu_memory: Some(64 * 1024), ..DeviceOptions::VALIDATED };
    let small = VulkanRenderer::new(DeviceSelector::Auto, options).expect("the same device again");
    let error = small.prepare(&scene).err().expect("64 KiB holds no 6,000 patches");
    assert!(error.to_string().contains("over the GPU memory budget of 0.1 MiB"), "{error}");
    let roomy = SceneLayout { memory_budget: Some(4 * used + (1 << 20)), ..SceneLayout::default() };
    assert!(small.prepare_with_layout(&scene, roomy).is_ok(), "the layout's budget wins");
    assert_no_validation_messages(&small);
    assert_no_validation_messages(&renderer);
}
