//! A scene made ready once for a backend: uploaded with its acceleration structures built
//! (Vulkan), or its BVHs built (CPU). Frames from other cameras trace it again as it is; a
//! large point set's upload and build take seconds, its frames milliseconds. On the GPU, a
//! point set over the memory budget streams: its tiles follow the camera
//! (`ReadyScene::stream_tiles`).

use pointray_cpu::CpuRenderer;
use pointray_scene::{Camera, RenderSettings};
use pointray_vulkan::{PreparedScene, TileResidency, VulkanRenderer};

use crate::error::BackendError;

pub enum ReadyScene {
    Vulkan(Box<PreparedScene>),
    Cpu(Box<CpuRenderer>),
}

impl ReadyScene {
    /// The camera of the next frames.
    pub fn set_camera(&mut self, camera: Camera) {
        match self {
            ReadyScene::Vulkan(prepared) => prepared.camera = camera,
            ReadyScene::Cpu(renderer) => renderer.set_camera(camera),
        }
    }

    /// Loads every tile the camera needs that the budget holds, evicting those it no longer
    /// does, for frames of `settings`' size; `None` where nothing streams.
    pub fn stream_tiles(&mut self, settings: &RenderSettings) -> Result<Option<TileResidency>, BackendError> {
        match self {
            ReadyScene::Vulkan(prepared) => Ok(prepared.stream_tiles(settings.aspect(), None)?),
            ReadyScene::Cpu(_) => Ok(None),
        }
    }
}

/// The renderer and the ready scene a frame is traced from (`Backend::tracer`).
pub enum Tracer<'a> {
    Vulkan(&'a VulkanRenderer, &'a PreparedScene),
    Cpu(&'a CpuRenderer),
}
