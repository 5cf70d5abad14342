//! The public face of the backend: pick a device, prepare scenes, trace frames.

use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use pointray_scene::{Integrator, RenderSettings, RenderedImage, Scene};
use raw_window_handle::RawDisplayHandle;

use crate::binding_table::ShaderBindingTable;
use crate::context::GpuContext;
use crate::device::{DeviceInfo, DeviceOptions, DeviceSelector};
use crate::error::VulkanError;
use crate::pipeline::RayTracingPipeline;
use crate::prepared_scene::{PreparedScene, SceneLayout, prepare};
use crate::shaders;
use crate::trace::trace_into;
use crate::trace_target::{PixelOutput, TraceTarget};
use crate::validation::MessageCounter;

/// How long one trace took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceTiming {
    /// GPU time between timestamps around `vkCmdTraceRaysKHR`; `None` without timestamps.
    pub gpu: Option<Duration>,
    /// Wall time of the call: setup (allocation on a target's first use), trace and copy-out.
    pub wall: Duration,
}

/// A ray-tracing renderer on one Vulkan device.
pub struct VulkanRenderer {
    // Field order is drop order: the tables and pipelines go before the device context.
    /// The path integrator's pipeline and table, built on the first trace that needs them
    /// and kept (targets' descriptor sets are allocated with its layout): renderers that
    /// never path trace (Table 1, Whitted windows) pay nothing for them.
    path: OnceLock<(RayTracingPipeline, ShaderBindingTable)>,
    /// Ray lists' pipeline and table (`cast_rays`), likewise built on first use.
    ray_list: OnceLock<(RayTracingPipeline, ShaderBindingTable)>,
    pub(crate) table: ShaderBindingTable,
    pub(crate) pipeline: RayTracingPipeline,
    pub(crate) context: Arc<GpuContext>,
}

impl VulkanRenderer {
    /// A renderer on the selected device.
    pub fn new(selector: DeviceSelector, options: DeviceOptions) -> Result<Self, VulkanError> {
        Self::with_raygen(&Arc::new(GpuContext::new(&selector, options, None)?), shaders::PRIMARY_RGEN)
    }

    /// A renderer with the Khronos validation layer on or off, and the other options at
    /// their defaults.
    pub fn with_validation(selector: DeviceSelector, validation: bool) -> Result<Self, VulkanError> {
        Self::new(selector, DeviceOptions { validation, ..DeviceOptions::default() })
    }

    /// A renderer that can also present to windows of `display`'s window system: its
    /// instance has the surface extensions and its device `VK_KHR_swapchain` (an error naming
    /// the device when it has none). Present with a `WindowTarget`.
    pub fn for_window(
        selector: DeviceSelector,
        options: DeviceOptions,
        display: RawDisplayHandle,
    ) -> Result<Self, VulkanError> {
        let context = GpuContext::new(&selector, options, Some(display))?;
        Self::with_raygen(&Arc::new(context), shaders::PRIMARY_RGEN)
    }

    /// A renderer that traces every path segment with shader execution reordering
    /// (`VK_NV_ray_tracing_invocation_reorder`): the same pictures, for comparing speed. An
    /// error on devices without it.
    pub fn with_hit_reordering(
        selector: DeviceSelector,
        options: DeviceOptions,
    ) -> Result<Self, VulkanError> {
        let options = DeviceOptions { hit_reordering: true, ..options };
        let context = Arc::new(GpuContext::new(&selector, options, None)?);
        if !context.info.hit_reordering {
            return Err(VulkanError::InvalidSettings(format!(
                "{} does not offer shader execution reordering (VK_NV_ray_tracing_invocation_reorder)",
                context.info.name
            )));
        }
        Self::with_raygen(&context, shaders::PRIMARY_REORDERING_RGEN)
    }

    fn with_raygen(context: &Arc<GpuContext>, raygen: &[u8]) -> Result<Self, VulkanError> {
        let pipeline = RayTracingPipeline::with_raygen(context, raygen, Integrator::Whitted)?;
        let table = ShaderBindingTable::new(context, &pipeline)?;
        Ok(Self {
            path: OnceLock::new(),
            ray_list: OnceLock::new(),
            table,
            pipeline,
            context: context.clone(),
        })
    }

    pub fn device_name(&self) -> &str {
        &self.context.info.name
    }

    pub fn device_info(&self) -> &DeviceInfo {
        &self.context.info
    }

    /// Warnings and errors the validation layer has reported so far (0 when it is off).
    pub fn validation_messages(&self) -> u32 {
        self.context.validation_messages()
    }

    /// The counter behind `validation_messages`; it keeps counting through the renderer's
    /// drop, so that objects leaked at teardown (reported by the layer then) can be counted.
    pub fn message_counter(&self) -> Arc<MessageCounter> {
        self.context.message_counter()
    }

    /// Uploads `scene` for traces with split hot and cold buffers (the default) and builds
    /// its acceleration structures (one geometry per point set).
    pub fn prepare(&self, scene: &Scene) -> Result<PreparedScene, VulkanError> {
        self.prepare_with_layout(scene, SceneLayout::default())
    }

    /// As `prepare`, with a chosen BLAS and buffer layout (the benchmark's ablations).
    pub fn prepare_with_layout(
        &self,
        scene: &Scene,
        layout: SceneLayout,
    ) -> Result<PreparedScene, VulkanError> {
        prepare(&self.context, scene, layout)
    }

    /// Traces a prepared scene into a frame (colour and AOVs).
    pub fn trace(
        &self,
        scene: &PreparedScene,
        settings: &RenderSettings,
    ) -> Result<RenderedImage, VulkanError> {
        self.trace_timed(scene, settings).map(|(frame, _)| frame)
    }

    /// As `trace`, also returning how long it took.
    pub fn trace_timed(
        &self,
        scene: &PreparedScene,
        settings: &RenderSettings,
    ) -> Result<(RenderedImage, TraceTiming), VulkanError> {
        let mut target = TraceTarget::new(PixelOutput::Aovs);
        let timing = self.trace_into(scene, settings, &mut target)?;
        Ok((target.image()?, timing))
    }

    /// Traces a prepared scene into a reusable target, from the scene's current camera and
    /// lights; read the result with `TraceTarget::frame` or `TraceTarget::display_rgba8`.
    /// The target keeps its GPU buffers between calls of the same image size.
    pub fn trace_into(
        &self,
        scene: &PreparedScene,
        settings: &RenderSettings,
        target: &mut TraceTarget,
    ) -> Result<TraceTiming, VulkanError> {
        self.ensure_prepared_here(scene)?;
        let start = Instant::now();
        let (pipeline, table) = self.pipeline_for(settings.integrator)?;
        let gpu = trace_into(&self.context, pipeline, table, scene, settings, target)?;
        Ok(TraceTiming { gpu, wall: start.elapsed() })
    }

    /// Scenes hold GPU resources of the renderer that prepared them; no other may trace them.
    /// The pipeline and binding table that trace with `integrator`.
    pub(crate) fn pipeline_for(
        &self,
        integrator: Integrator,
    ) -> Result<(&RayTracingPipeline, &ShaderBindingTable), VulkanError> {
        if integrator == Integrator::Whitted {
            return Ok((&self.pipeline, &self.table));
        }
        self.built(&self.path, shaders::PATH_RGEN, Integrator::Path)
    }

    /// The pipeline and binding table of ray lists. Their ray generation shades nothing, so
    /// no integrator applies; no frame is traced with it.
    pub(crate) fn ray_list_pipeline(
        &self,
    ) -> Result<(&RayTracingPipeline, &ShaderBindingTable), VulkanError> {
        self.built(&self.ray_list, shaders::RAY_LIST_RGEN, Integrator::Whitted)
    }

    /// The pipeline and table in `slot`, built with `raygen` on the first call.
    fn built<'a>(
        &self,
        slot: &'a OnceLock<(RayTracingPipeline, ShaderBindingTable)>,
        raygen: &[u8],
        integrator: Integrator,
    ) -> Result<(&'a RayTracingPipeline, &'a ShaderBindingTable), VulkanError> {
        if slot.get().is_none() {
            let pipeline = RayTracingPipeline::with_raygen(&self.context, raygen, integrator)?;
            let table = ShaderBindingTable::new(&self.context, &pipeline)?;
            // Only `&self` builds it; a racing build's copy is dropped.
            let _ = slot.set((pipeline, table));
        }
        let (pipeline, table) = slot.get().expect("built above");
        Ok((pipeline, table))
    }

    pub(crate) fn ensure_prepared_here(&self, scene: &PreparedScene) -> Result<(), VulkanError> {
        if !Arc::ptr_eq(&scene.context, &self.context) {
            return Err(VulkanError::InvalidScene("the scene was prepared by another renderer".into()));
        }
        scene.check_traceable()
    }

    /// Prepares and traces in one go.
    pub fn render(&self, scene: &Scene, settings: &RenderSettings) -> Result<RenderedImage, VulkanError> {
        self.trace(&self.prepare_with_layout(scene, SceneLayout::for_settings(settings))?, settings)
    }
}
