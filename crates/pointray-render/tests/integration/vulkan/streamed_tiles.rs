//! A point set over its GPU memory budget, streamed: the tiles a camera sees are loaded as far
//! as the budget allows, and draw what the whole set draws there; moving the camera evicts
//! tiles it no longer sees and loads the ones it now does, within the budget.

use std::time::Duration;

use super::point_colors::{coloured_sphere, lit_on_floor};
use super::tiles::{assert_same_hits, bunny_object, patch_count};

use glam::Vec3;
use std::sync::Arc;

use pointray_kernels::{Aabb, PatchCold, PatchHot};
use pointray_patches::PatchSet;
use pointray_scene::{Background, Geometry, Material};
use pointray_scene::{Camera, RenderSettings, RenderedImage, Scene};
use pointray_test_support::floor_scenes::{mesh, model_on_floor, object, point_light, settings};
use pointray_test_support::{assert_no_validation_messages, vulkan_renderer};
use pointray_vulkan::{HotRecords, PreparedScene, SceneLayout, TileResidency, VulkanError, VulkanRenderer};

const SIZE: u32 = 96;

/// About 35 tiles of the bunny's 35,000 patches.
const TILE: u32 = 1000;

/// The bunny on a floor that neither reflects nor, as nothing casts shadows, shows what the
/// tiles out of view would add: a view's image depends on the tiles it sees alone.
fn bunny_scene() -> (Scene, Aabb) {
    let (bunny, bounds) = bunny_object(&pointray_test_support::data_file("points/bunny.ply"));
    (model_on_floor(bunny, bounds, 0.0), bounds)
}

fn unshadowed() -> RenderSettings {
    RenderSettings { shadows: false, max_depth: 1, ..settings(SIZE) }
}

/// A close view of the bunny's `side` (-1 or 1 along x), a narrow one that sees part of it.
fn close_view(bounds: &Aabb, side: f32) -> Camera {
    let (min, max) = (Vec3::from(bounds.min), Vec3::from(bounds.max));
    let size = (max - min).max_element();
    let center = 0.5 * (min + max);
    let target = Vec3::new(if side < 0.0 { min.x } else { max.x }, center.y, center.z);
    Camera {
        position: target + Vec3::new(0.3 * side * size, 0.0, 0.3 * size),
        look_at: target,
        up: Vec3::Y,
        vertical_fov_degrees: 20.0,
    }
}

fn streamed(
    renderer: &VulkanRenderer,
    scene: &Scene,
    budget: u64,
    tile: u32,
) -> Result<PreparedScene, VulkanError> {
    let layout = SceneLayout {
        memory_budget: Some(budget),
        stream_tiles_for: Some((SIZE, SIZE)),
        max_tile_patches: Some(tile),
        ..SceneLayout::default()
    };
    renderer.prepare_with_layout(scene, layout)
}

/// `scene` streamed in three quarters of what it takes whole.
fn streamed_in_three_quarters(renderer: &VulkanRenderer, scene: &Scene) -> PreparedScene {
    let budget = renderer.prepare(scene).expect("prepares whole").build_report().gpu_bytes() * 3 / 4;
    streamed(renderer, scene, budget, TILE).expect("streams within the budget")
}

fn stream(prepared: &mut PreparedScene, camera: Camera, limit: Option<Duration>) -> TileResidency {
    prepared.camera = camera;
    let residency = prepared.stream_tiles(1.0, limit).expect("streams").expect("the bunny streams");
    eprintln!("{residency:?}");
    residency
}

fn whole_image(renderer: &VulkanRenderer, whole: &mut PreparedScene, camera: Camera) -> RenderedImage {
    whole.camera = camera;
    renderer.trace(whole, &unshadowed()).expect("traces whole")
}

#[test]
fn a_cloud_over_its_budget_streams_the_tiles_each_view_sees_and_draws_what_it_draws_whole() {
    let Some(renderer) = vulkan_renderer() else { return };
    let (scene, bounds) = bunny_scene();
    let mut whole = renderer.prepare(&scene).expect("prepares whole");
    let whole_bytes = whole.build_report().gpu_bytes();
    let budget = whole_bytes * 3 / 4;
    let mut prepared = streamed(&renderer, &scene, budget, TILE).expect("streams within the budget");
    for side in [-1.0, 1.0, -1.0] {
        let camera = close_view(&bounds, side);
        let residency = stream(&mut prepared, camera, None);
        assert!(residency.tiles >= 30, "{residency:?}: {} patches", patch_count(&scene));
        assert!(residency.resident < residency.tiles, "{residency:?}: the budget holds some tiles only");
        assert_eq!(residency.in_view_resident, residency.in_view, "{residency:?}: every tile in view fits");
        assert_eq!(residency.pending, 0, "{residency:?}");
        assert!(residency.resident_bytes <= residency.budget_bytes, "{residency:?}");
        let report = prepared.build_report();
        let (held, peak) = (report.gpu_bytes(), report.peak_build_bytes);
        assert!(held <= budget, "the streamed scene holds {held} bytes, over its budget of {budget}");
        assert!(peak >= held && peak <= budget, "{report:?}: its peak is over its budget of {budget}");
        let image = renderer.trace(&prepared, &unshadowed()).expect("traces streamed");
        assert!(image.hit_mask().iter().filter(|&&hit| hit).count() > (SIZE * SIZE / 4) as usize);
        let name = format!("bunny streamed, seen from side {side}");
        assert_same_hits(&name, &image, &whole_image(&renderer, &mut whole, camera));
    }
    assert_no_validation_messages(&renderer);
}

#[test]
fn streamed_tiles_of_unpacked_records_draw_what_the_whole_unpacked_set_draws() {
    let Some(renderer) = vulkan_renderer() else { return };
    let (scene, bounds) = bunny_scene();
    let unpacked = SceneLayout { hot_records: HotRecords::Unpacked, ..SceneLayout::default() };
    let mut whole = renderer.prepare_with_layout(&scene, unpacked).expect("prepares whole");
    let budget = whole.build_report().gpu_bytes() * 3 / 4;
    let layout = SceneLayout {
        memory_budget: Some(budget),
        stream_tiles_for: Some((SIZE, SIZE)),
        max_tile_patches: Some(TILE),
        ..unpacked
    };
    let mut prepared = renderer.prepare_with_layout(&scene, layout).expect("streams within the budget");
    let camera = close_view(&bounds, 1.0);
    let residency = stream(&mut prepared, camera, None);
    assert!(residency.resident < residency.tiles, "{residency:?}: the budget holds some tiles only");
    assert_eq!(prepared.build_report().hot_records, HotRecords::Unpacked);
    let image = renderer.trace(&prepared, &unshadowed()).expect("traces streamed");
    assert_same_hits("unpacked bunny streamed", &image, &whole_image(&renderer, &mut whole, camera));
    assert_no_validation_messages(&renderer);
}

#[test]
fn turning_to_another_view_evicts_tiles_and_a_time_limit_loads_one_tile_a_call() {
    let Some(renderer) = vulkan_renderer() else { return };
    let (scene, bounds) = bunny_scene();
    let mut prepared = streamed_in_three_quarters(&renderer, &scene);
    let first = stream(&mut prepared, close_view(&bounds, -1.0), None);
    let turned = stream(&mut prepared, close_view(&bounds, 1.0), Some(Duration::ZERO));
    assert!(turned.evicted > 0 && turned.loaded == 1, "{turned:?} after {first:?}");
    let mut pending = turned.pending;
    assert!(pending > 0, "{turned:?}: more than one tile is wanted");
    while pending > 0 {
        let next = stream(&mut prepared, close_view(&bounds, 1.0), Some(Duration::ZERO));
        assert_eq!((next.loaded, next.evicted, next.pending), (1, 0, pending - 1), "{next:?}");
        pending = next.pending;
    }
    let settled = stream(&mut prepared, close_view(&bounds, 1.0), None);
    assert!(!settled.changed(), "{settled:?}: a settled view loads nothing");
    assert_no_validation_messages(&renderer);
}

#[test]
fn the_first_update_reports_the_tiles_the_preparation_loaded() {
    let Some(renderer) = vulkan_renderer() else { return };
    let (scene, _) = bunny_scene();
    let mut prepared = streamed_in_three_quarters(&renderer, &scene);
    let first = stream(&mut prepared, scene.camera, None);
    assert!(first.loaded > 0 && first.loaded == first.resident, "{first:?}: the preparation's loads");
    let again = stream(&mut prepared, scene.camera, None);
    assert_eq!((again.loaded, again.evicted), (0, 0), "{again:?}: reported once");
    assert_no_validation_messages(&renderer);
}

#[test]
fn a_budget_without_room_for_one_tile_is_refused_and_a_roomy_one_uploads_the_set_whole() {
    let Some(renderer) = vulkan_renderer() else { return };
    let (scene, _) = bunny_scene();
    let error = streamed(&renderer, &scene, 64 * 1024, TILE).err().expect("64 KiB streams nothing");
    assert!(matches!(error, VulkanError::OverBudget(_)), "{error:?}");
    assert!(error.to_string().contains("streaming the point sets' tiles"), "{error}");
    let mut roomy = streamed(&renderer, &scene, 1 << 30, TILE).expect("a roomy budget uploads whole");
    let tiles = patch_count(&scene).div_ceil(TILE as usize);
    assert_eq!(roomy.build_report().blas_count, tiles + 1, "every tile of the bunny, and the floor");
    assert_eq!(roomy.stream_tiles(1.0, None).expect("nothing to stream"), None);
    assert_no_validation_messages(&renderer);
}

/// A flat grid of `side` x `side` round patches, a unit apart, far larger than the bunny so
/// that its streamed tiles hold more than the fewest a tile may.
fn grid_scene(side: u32) -> Scene {
    let hot: Vec<PatchHot> = (0..side * side)
        .map(|i| Vec3::new((i % side) as f32, 0.0, (i / side) as f32))
        .map(|origin| PatchHot::isotropic(origin, Vec3::X, Vec3::Y, [0.0; 6], 1.0))
        .collect();
    let aabbs = hot.iter().map(|patch| Aabb::cube(patch.origin(), patch.radius())).collect();
    let patches = PatchSet {
        aabbs,
        cold: vec![PatchCold::default(); hot.len()].into(),
        hot: hot.into(),
        ..PatchSet::default()
    };
    let bounds = Aabb { min: [0.0; 3], max: [side as f32, 0.0, side as f32] };
    Scene {
        camera: Scene::framing_camera(&bounds, Vec3::new(0.3, 0.4, 1.0), 40.0, 1.0),
        lights: vec![point_light(Vec3::new(0.0, side as f32, 0.0), 1.0)],
        background: Background::Solid(Vec3::splat(0.2)),
        objects: vec![object("grid", Geometry::Patches(Arc::new(patches)), Material::default())],
    }
}

#[test]
fn a_budget_too_small_for_a_sets_usual_tiles_streams_smaller_ones() {
    let Some(renderer) = vulkan_renderer() else { return };
    let scene = grid_scene(800);
    let streams_in = |budget: u64, tile: Option<u32>| {
        let layout = SceneLayout {
            memory_budget: Some(budget),
            stream_tiles_for: Some((SIZE, SIZE)),
            max_tile_patches: tile,
            ..SceneLayout::default()
        };
        renderer.prepare_with_layout(&scene, layout)
    };
    // The least budget that streams tiles of half the usual 10,000 patches.
    let (mut refused, mut streams) = (1u64 << 16, 1u64 << 30);
    while streams - refused > 1 << 12 {
        let middle = (refused + streams) / 2;
        match streams_in(middle, Some(5000)) {
            Ok(_) => streams = middle,
            Err(_) => refused = middle,
        }
    }
    let tiles_in = |budget: u64| {
        let mut prepared = streams_in(budget, None).expect("streams");
        prepared.stream_tiles(1.0, None).expect("streams").expect("the grid streams").tiles
    };
    assert_eq!(tiles_in(4 * streams), 64, "a roomier budget keeps the usual tiles of 10,000 patches");
    assert_eq!(tiles_in(streams), 128, "where those do not fit, tiles of 5,000 stream");
    assert_no_validation_messages(&renderer);
}

#[test]
fn a_mesh_whose_build_does_not_fit_is_refused_by_name_not_built_past_the_budget() {
    let Some(renderer) = vulkan_renderer() else { return };
    let (mut scene, _) = bunny_scene();
    let sphere = pointray_test_support::sphere_mesh(1.0, 400, 800);
    scene.objects.push(object("sphere", mesh(sphere), Default::default()));
    let error = streamed(&renderer, &scene, 2 << 20, TILE).err().expect("2 MiB holds no 640,000 triangles");
    assert!(matches!(error, VulkanError::OverBudget(_)), "{error:?}");
    assert!(error.to_string().contains("a mesh's"), "{error}");
    assert_no_validation_messages(&renderer);
}

#[test]
fn a_coloured_cloud_streams_with_its_colours_blended_across_its_tiles_as_whole() {
    let Some(renderer) = vulkan_renderer() else { return };
    let mut scene = lit_on_floor(coloured_sphere());
    scene.objects[1].material.reflectivity = 0.0;
    let mut whole = renderer.prepare(&scene).expect("prepares whole");
    // Tiles of 250 patches carry colour halos nearly their own size.
    let budget = whole.build_report().gpu_bytes() * 9 / 10;
    let mut prepared = streamed(&renderer, &scene, budget, 250).expect("streams within the budget");
    // A narrow view of the sphere's right edge (its radius is 0.8), which passes through a
    // few of its tiles: the tiles of a shell hold the shell's inside in their boxes.
    let center: Vec3 = scene.objects[0].transform.translation.into();
    let edge = center + Vec3::new(0.7, 0.0, 0.0);
    let camera = Camera {
        position: edge + Vec3::new(0.0, 0.0, 3.0),
        look_at: edge,
        up: Vec3::Y,
        vertical_fov_degrees: 5.0,
    };
    let residency = stream(&mut prepared, camera, None);
    assert!(residency.resident < residency.tiles, "{residency:?}");
    assert_eq!(residency.in_view_resident, residency.in_view, "{residency:?}");
    let image = renderer.trace(&prepared, &unshadowed()).expect("traces streamed");
    let hits = image.hit_mask().iter().filter(|&&hit| hit).count();
    assert!(hits > (SIZE * SIZE / 8) as usize, "{hits} pixels see the sphere");
    let reference = whole_image(&renderer, &mut whole, camera);
    let psnr = image.color_psnr(&reference);
    eprintln!("coloured sphere streamed: {psnr:.1} dB");
    // Blends that stopped at tile borders left seams at 57.7 dB.
    assert!(psnr >= 90.0, "{psnr:.1} dB");
    assert_no_validation_messages(&renderer);
}
