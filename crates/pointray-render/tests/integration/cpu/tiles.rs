//! Point sets in tiles on the CPU: one BVH per run of patches under the top level finds the
//! same hits as one BVH per set.

use pointray_cpu::CpuRenderer;
use pointray_scene::{Geometry, RenderSettings, demo_scene};

#[test]
fn the_demo_in_many_tiles_finds_the_same_hits() {
    let scene = demo_scene().expect("the demo scene builds");
    let patches: Vec<usize> = scene
        .objects
        .iter()
        .filter_map(|object| match &object.geometry {
            Geometry::Patches(set) => Some(set.len()),
            Geometry::Mesh(_) => None,
        })
        .collect();
    let meshes = scene.objects.len() - patches.len();
    let max_tile = 97;
    let tiled = CpuRenderer::with_max_tile_patches(&scene, max_tile);
    let whole = CpuRenderer::new(&scene);
    let tiles: usize = patches.iter().map(|count| count.div_ceil(max_tile)).sum();
    assert!(tiles >= 40, "{tiles} tiles");
    assert_eq!(tiled.tile_count(), tiles + meshes);
    assert_eq!(whole.tile_count(), scene.objects.len());
    let settings = RenderSettings { width: 96, height: 96, ..RenderSettings::default() };
    let (a, b) = (tiled.render(&settings), whole.render(&settings));
    let depth_bits =
        |image: &pointray_scene::RenderedImage| image.depth.iter().map(|d| d.to_bits()).collect::<Vec<_>>();
    assert_eq!(a.instance_id, b.instance_id, "the same objects");
    assert_eq!(depth_bits(&a), depth_bits(&b), "the same nearest depths");
    // Where two overlapping patches tie at one depth either may be kept; elsewhere the
    // patch, and so its normal, is the same. Reflected rays may tie too, so the colours
    // need only agree closely.
    let same_patch = (0..a.pixel_count()).filter(|&i| a.primitive_id[i] == b.primitive_id[i]);
    for i in same_patch {
        assert_eq!(a.normal[i], b.normal[i], "pixel {i}");
    }
    let squared: f32 = a.color.iter().zip(&b.color).map(|(x, y)| (*x - *y).length_squared() / 3.0).sum();
    let psnr = 10.0 * (a.pixel_count() as f32 / squared.max(f32::MIN_POSITIVE)).log10();
    assert!(psnr >= 60.0, "tiled and whole images differ: {psnr:.1} dB");
    let hits = a.hit_mask().iter().filter(|&&hit| hit).count();
    assert!(hits > a.pixel_count() / 4, "the demo fills the view: {hits} hits");
}
