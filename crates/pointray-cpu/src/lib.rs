//! The CPU reference renderer: pure Rust, rayon over pixel tiles, a BVH per object (obvhs
//! CWBVH over patch boxes or triangles) under a BVH over object instances. It follows the
//! rendering contract of docs/ARCHITECTURE.md with the maths of `pointray-kernels`, the
//! same functions the Vulkan shaders include, so both backends draw the same image.
//!
//! A `CpuRenderer` builds its BVHs once; its camera and lights can then be changed between
//! frames (`set_camera`, `set_lights`) without rebuilding anything.

mod direct_light;
mod first_hit;
mod instance;
mod object_bvh;
mod path_tracer;
mod ray_counts;
mod renderer;
mod scene_updates;
mod shading;
mod top_level;
mod triangle;
mod whitted;

pub use first_hit::RayHit;
pub use ray_counts::RayCounts;
pub use renderer::CpuRenderer;

use pointray_scene::{RenderSettings, RenderedImage, Scene};

/// Builds the acceleration structures and renders one frame. To render several frames of
/// one scene, build a `CpuRenderer` once instead.
pub fn render(scene: &Scene, settings: &RenderSettings) -> RenderedImage {
    CpuRenderer::new(scene).render(settings)
}
