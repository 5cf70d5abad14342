//! The CPU renderer: acceleration structures built once, images rendered in parallel
//! over pixel tiles.

use glam::{UVec2, Vec3};
use pointray_kernels::{Camera, EmissiveTriangles, Ray, camera_ray, random_sequence, sample_jitter};
use pointray_scene::{Integrator, RenderSettings, RenderedImage, Scene};
use rayon::prelude::*;

use crate::ray_counts::RayCounts;
use crate::top_level::{SceneHit, TopLevel};
use crate::whitted::PrimaryAov;

/// Tiles are squares of this many pixels a side: small enough to balance two to many
/// cores, large enough that neighbouring rays share BVH nodes in cache.
const TILE_SIZE: u32 = 16;

/// The scene's BVHs, built once, and the scene itself, whose camera and lights may change
/// between images (`scene_updates.rs`).
pub struct CpuRenderer {
    pub(crate) scene: Scene,
    pub(crate) top: TopLevel,
    pub(crate) ray_epsilon: f32,
    /// The emissive mesh triangles, one light for the path integrator's light sampling.
    pub(crate) emissive: EmissiveTriangles,
}

/// One pixel's result.
#[derive(Clone, Copy)]
struct Pixel {
    color: Vec3,
    aov: PrimaryAov,
}

impl CpuRenderer {
    /// Builds every object's BVH and the top level once; objects with nothing to hit or a
    /// singular transform are left out (with a warning).
    pub fn new(scene: &Scene) -> Self {
        Self::with_max_tile_patches(scene, usize::MAX)
    }

    /// As `new`, with each point set split into tiles of at most `max_tile_patches` patches
    /// (`pointray_patches::patch_tiles`), one BVH each under the top level: the same hits,
    /// and a large set's BVHs build in parallel.
    pub fn with_max_tile_patches(scene: &Scene, max_tile_patches: usize) -> Self {
        Self {
            scene: scene.clone(),
            top: TopLevel::build(scene, max_tile_patches),
            ray_epsilon: scene.ray_epsilon(),
            emissive: scene.emissive_triangles(),
        }
    }

    /// How many bottom-level BVHs (tiles of point sets, meshes) the scene was built into.
    pub fn tile_count(&self) -> usize {
        self.top.instances.len()
    }

    /// Renders one image. Zero samples per pixel count as one.
    pub fn render(&self, settings: &RenderSettings) -> RenderedImage {
        self.render_counting_rays(settings).0
    }

    /// Renders one image and says how many rays of each kind it traced.
    pub fn render_counting_rays(&self, settings: &RenderSettings) -> (RenderedImage, RayCounts) {
        let (width, height) = (settings.width, settings.height);
        let tiles: Vec<UVec2> = (0..height.div_ceil(TILE_SIZE))
            .flat_map(|ty| (0..width.div_ceil(TILE_SIZE)).map(move |tx| UVec2::new(tx, ty) * TILE_SIZE))
            .collect();
        let rendered: Vec<(UVec2, Vec<Pixel>, RayCounts)> = tiles
            .par_iter()
            .map(|&corner| {
                let mut counts = RayCounts::default();
                (corner, self.render_tile(corner, settings, &mut counts), counts)
            })
            .collect();
        let mut image = empty_image(width, height);
        if settings.integrator == Integrator::Path {
            image.albedo = Some(vec![Vec3::ZERO; image.pixel_count()]);
        }
        let mut total = RayCounts::default();
        for (corner, pixels, counts) in rendered {
            total += counts;
            for (pixel, result) in tile_pixels(corner, width, height).zip(pixels) {
                let index = (pixel.y * width + pixel.x) as usize;
                image.color[index] = result.color;
                image.depth[index] = result.aov.depth;
                image.normal[index] = result.aov.normal;
                image.instance_id[index] = result.aov.instance_id;
                image.primitive_id[index] = result.aov.primitive_id;
                if let Some(albedo) = &mut image.albedo {
                    albedo[index] = result.aov.albedo;
                }
            }
        }
        (image, total)
    }

    fn render_tile(&self, corner: UVec2, settings: &RenderSettings, counts: &mut RayCounts) -> Vec<Pixel> {
        let camera = self.scene.camera;
        let size = UVec2::new(settings.width, settings.height);
        tile_pixels(corner, settings.width, settings.height)
            .map(|pixel| self.render_pixel(&camera, size, pixel, settings, counts))
            .collect()
    }

    /// The average over the pixel's samples; AOVs from the first.
    fn render_pixel(
        &self,
        camera: &Camera,
        size: UVec2,
        pixel: UVec2,
        settings: &RenderSettings,
        counts: &mut RayCounts,
    ) -> Pixel {
        let samples = settings.samples_per_pixel.max(1);
        let mut sample = |s| {
            let ray = camera_ray(camera, size, pixel, sample_jitter(s));
            match settings.integrator {
                Integrator::Whitted => self.trace_whitted(ray, settings, counts),
                Integrator::Path => {
                    self.path_trace(ray, random_sequence(settings.seed, pixel, s), settings, counts)
                }
            }
        };
        let first = settings.first_sample;
        let (first_color, aov) = sample(first);
        let rest: Vec3 = (first + 1..first.saturating_add(samples)).map(|s| sample(s).0).sum();
        Pixel { color: (first_color + rest) / samples as f32, aov }
    }

    pub(crate) fn closest_hit(&self, ray: &Ray, t_min: f32, settings: &RenderSettings) -> Option<SceneHit> {
        self.top.closest_hit(ray, t_min, f32::INFINITY, settings.acceptance)
    }

    pub(crate) fn occluded(&self, ray: &Ray, t_min: f32, distance: f32, settings: &RenderSettings) -> bool {
        self.top.occluded(ray, t_min, distance, settings.acceptance)
    }
}

/// The pixels of the tile at `corner`, clipped to the image, row by row.
fn tile_pixels(corner: UVec2, width: u32, height: u32) -> impl Iterator<Item = UVec2> {
    let end = (corner + TILE_SIZE).min(UVec2::new(width, height));
    (corner.y..end.y).flat_map(move |y| (corner.x..end.x).map(move |x| UVec2::new(x, y)))
}

fn empty_image(width: u32, height: u32) -> RenderedImage {
    let count = width as usize * height as usize;
    RenderedImage {
        width,
        height,
        color: vec![Vec3::ZERO; count],
        depth: vec![f32::INFINITY; count],
        normal: vec![Vec3::ZERO; count],
        instance_id: vec![RenderedImage::MISS; count],
        primitive_id: vec![RenderedImage::MISS; count],
        albedo: None,
    }
}
