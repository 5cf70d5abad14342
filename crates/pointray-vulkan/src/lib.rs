//! The Vulkan ray-tracing renderer (METHOD.md §3): point sets as procedural AABB geometry with
//! a quadratic-patch intersection shader, meshes as triangles, shaded by an iterative path in
//! ray generation (ARCHITECTURE.md, rendering contract).
//!
//! ```no_run
//! # fn demo(scene: &pointray_scene::Scene) -> Result<(), pointray_vulkan::VulkanError> {
//! use pointray_vulkan::{DeviceOptions, DeviceSelector, VulkanRenderer};
//! let renderer = VulkanRenderer::new(DeviceSelector::Auto, DeviceOptions::default())?;
//! let prepared = renderer.prepare(scene)?;
//! let frame = renderer.trace(&prepared, &pointray_scene::RenderSettings::default())?;
//! # let _ = frame; Ok(()) }
//! ```

mod acceleration;
mod barrier;
mod binding_table;
mod buffer;
mod color_halo;
mod context;
mod descriptor_set;
mod device;
mod device_type;
mod error;
mod frame_loop;
mod gpu_records;
mod instance;
mod kept_buffers;
mod light_table;
mod memory_plan;
mod memory_report;
mod patch_upload;
mod pipeline;
mod prepared_scene;
mod present_device;
mod present_loop;
mod ray_counter;
mod ray_list;
mod renderer;
mod shaders;
#[cfg(test)]
mod spirv_reflection;
mod surface_choice;
mod swapchain;
mod tile_stream;
mod tile_view;
mod timestamp_pool;
mod trace;
mod trace_target;
#[cfg(test)]
mod twin_agreement;
#[cfg(test)]
mod twin_probe;
pub mod validation;
mod window_target;

pub use acceleration::BlasLayout;
pub use device::{DeviceInfo, DeviceOptions, DeviceSelector, list_devices};
pub use device_type::DeviceType;
pub use error::VulkanError;
pub use frame_loop::FrameLoopTimes;
pub use gpu_records::{ListedRay, RayHit, RayPose};
pub use memory_report::BuildReport;
pub use pointray_scene::HotRecords;
pub use prepared_scene::{PATCHES_PER_BOX_TO_FIT, PreparedScene, SceneLayout, UNPACKED_MOST_PATCHES};
pub use present_device::PresentDevice;
pub use present_loop::{PresentLoop, Presented};
pub use ray_counter::RayCounts;
pub use ray_list::RayListTarget;
pub use renderer::{TraceTiming, VulkanRenderer};
pub use swapchain::{Swapchain, SwapchainDevice, record_copy_to_present_image};
pub use tile_stream::TileResidency;
pub use trace_target::{PixelOutput, TraceTarget};
pub use validation::MessageCounter;
pub use window_target::{DisplayImage, ReadBack, WindowTarget};
