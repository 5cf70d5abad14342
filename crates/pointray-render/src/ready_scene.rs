//! A scene made ready once for a backend: uploaded with its acceleration structures built
//! (Vulkan), or its BVHs built (CPU). Frames from other cameras trace it again as it is; a
//! large point set's upload and build take seconds, its frames milliseconds.

use pointray_cpu::CpuRenderer;
use pointray_scene::Camera;
use pointray_vulkan::{PreparedScene, VulkanRenderer};

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
}

/// The renderer and the ready scene a frame is traced from (`Backend::tracer`).
pub enum Tracer<'a> {
    Vulkan(&'a VulkanRenderer, &'a PreparedScene),
    Cpu(&'a CpuRenderer),
}
