//! What a trace writes into and reads back from: the frame uniforms, the output buffer, its
//! host-visible copy and the descriptor set. A target lives across traces, so a viewer or a
//! benchmark allocates once and re-allocates only when the image size changes.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;
use pointray_kernels::packing::unpack_half2x16;
use pointray_scene::{Integrator, RenderSettings, RenderedImage};

use crate::buffer::Buffer;
use crate::context::GpuContext;
use crate::descriptor_set::{StorageRange, TraceDescriptors};
use crate::error::VulkanError;
use crate::gpu_records::PixelRecord;
use crate::kept_buffers::kept_or_made;
use crate::pipeline::{
    BINDING_ACCUMULATION, BINDING_DISPLAY_PIXELS, BINDING_INTERSECTION_CALLS, BINDING_LIGHTS, BINDING_PIXELS,
    RayTracingPipeline,
};
use crate::prepared_scene::PreparedScene;
use crate::timestamp_pool::TimestampPool;

/// What a trace writes per pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PixelOutput {
    /// Linear colour with the AOVs (normal, depth, ids): 48 bytes a pixel, for `RenderedImage`s.
    #[default]
    Aovs,
    /// sRGB8 RGBA colour only: 4 bytes a pixel, what a window shows.
    Display,
    /// As `Display` with blue in the low byte: what a B8G8R8A8 swapchain image holds.
    DisplayBgra,
}

impl PixelOutput {
    pub(crate) fn bytes_per_pixel(self) -> u64 {
        match self {
            PixelOutput::Aovs => std::mem::size_of::<PixelRecord>() as u64,
            PixelOutput::Display | PixelOutput::DisplayBgra => 4,
        }
    }

    /// The value the shaders receive for this output (`OUTPUT_*` in bindings.glsl).
    pub(crate) fn code(self) -> u32 {
        match self {
            PixelOutput::Aovs => 0,
            PixelOutput::Display => 1,
            PixelOutput::DisplayBgra => 2,
        }
    }
}

/// Reusable output of traces at one size; see `VulkanRenderer::trace_into`.
pub struct TraceTarget {
    output: PixelOutput,
    buffers: Option<TargetBuffers>,
    /// The integrator of the last trace: the path integrator's AOVs carry the albedo.
    integrator: Integrator,
}

/// The GPU side of a target, for one device and one image size.
pub(crate) struct TargetBuffers {
    context: Arc<GpuContext>,
    pub(crate) output: PixelOutput,
    width: u32,
    height: u32,
    /// The output the shaders write (`output`'s records); the other binding gets `unused`.
    pub(crate) written: Buffer,
    unused: Buffer,
    /// The display outputs' running sums (`unused` for the AOV output, which has none).
    accumulation: Option<Buffer>,
    /// Intersection-shader calls per pixel, for a counting pipeline only.
    pub(crate) intersection_calls: Option<Buffer>,
    pub(crate) readback: Buffer,
    pub(crate) descriptors: TraceDescriptors,
    pub(crate) timestamps: Option<TimestampPool>,
}

impl TraceTarget {
    pub fn new(output: PixelOutput) -> Self {
        Self { output, buffers: None, integrator: Integrator::Whitted }
    }

    pub fn output(&self) -> PixelOutput {
        self.output
    }

    /// The last trace as a image with its AOVs; an error for a display target or before any trace.
    pub fn image(&self) -> Result<RenderedImage, VulkanError> {
        match (&self.buffers, self.output) {
            (Some(buffers), PixelOutput::Aovs) => {
                let pixels: Vec<PixelRecord> = bytemuck::pod_collect_to_vec(buffers.readback.read());
                let with_albedo = self.integrator == Integrator::Path;
                Ok(image_from_pixels(buffers.width, buffers.height, &pixels, with_albedo))
            }
            _ => Err(VulkanError::InvalidSettings("this target holds no traced image with AOVs".into())),
        }
    }

    /// The last trace's sRGB8 RGBA pixels, rows top to bottom; an error for an AOV or BGRA
    /// target or before any trace.
    pub fn display_rgba8(&self) -> Result<&[u8], VulkanError> {
        match (&self.buffers, self.output) {
            (Some(_), PixelOutput::Display) => self.read_back(),
            _ => Err(VulkanError::InvalidSettings("this target holds no traced display image".into())),
        }
    }

    /// The intersection-shader calls of the last trace, summed over its pixels; `None` unless
    /// its pipeline counts them (`RayTracingPipeline::counting`).
    pub(crate) fn intersection_calls(&self) -> Option<u64> {
        let calls = self.buffers.as_ref()?.intersection_calls.as_ref()?;
        let per_pixel: Vec<u32> = bytemuck::pod_collect_to_vec(calls.read());
        Some(per_pixel.iter().map(|&calls| u64::from(calls)).sum())
    }

    /// The raw bytes the last trace copied out.
    pub(crate) fn read_back(&self) -> Result<&[u8], VulkanError> {
        match &self.buffers {
            Some(buffers) => Ok(buffers.readback.read()),
            None => Err(VulkanError::InvalidSettings("nothing was traced into this target yet".into())),
        }
    }

    /// The buffers for a trace of `scene` with `settings`, bound to it: made anew when the
    /// device or the size changed. No submitted trace may still use this target.
    pub(crate) fn bind(
        &mut self,
        context: &Arc<GpuContext>,
        pipeline: &RayTracingPipeline,
        scene: &PreparedScene,
        settings: &RenderSettings,
    ) -> Result<&TargetBuffers, VulkanError> {
        scene.check_buffers_for(settings)?;
        self.integrator = pipeline.integrator;
        let buffers = self.buffers_for(context, pipeline, settings.width, settings.height)?;
        buffers.bind(scene);
        Ok(buffers)
    }

    fn buffers_for(
        &mut self,
        context: &Arc<GpuContext>,
        pipeline: &RayTracingPipeline,
        width: u32,
        height: u32,
    ) -> Result<&mut TargetBuffers, VulkanError> {
        let output = self.output;
        // A counting pipeline's set layout has one binding more than the others'.
        let counting = pipeline.counts_intersections;
        kept_or_made(
            &mut self.buffers,
            |b| {
                Arc::ptr_eq(&b.context, context)
                    && (b.width, b.height) == (width, height)
                    && b.intersection_calls.is_some() == counting
            },
            || TargetBuffers::new(context, pipeline, width, height, output),
        )
    }
}

impl TargetBuffers {
    fn new(
        context: &Arc<GpuContext>,
        pipeline: &RayTracingPipeline,
        width: u32,
        height: u32,
        output: PixelOutput,
    ) -> Result<Self, VulkanError> {
        let bytes = u64::from(width) * u64::from(height) * output.bytes_per_pixel();
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
        let written = Buffer::new(context, "pixel output", bytes, usage, MemoryLocation::GpuOnly)?;
        // Storage bindings may not be null; the output not written gets one small buffer.
        let unused = Buffer::new(context, "unused pixel output", 64, usage, MemoryLocation::GpuOnly)?;
        let accumulation = match output {
            PixelOutput::Aovs => None,
            PixelOutput::Display | PixelOutput::DisplayBgra => {
                let bytes = u64::from(width) * u64::from(height) * 16;
                let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
                Some(Buffer::new(context, "display sums", bytes, usage, MemoryLocation::GpuOnly)?)
            }
        };
        // Host-visible: each trace's counts start from zeros written here and are read here.
        let intersection_calls = if pipeline.counts_intersections {
            let bytes = u64::from(width) * u64::from(height) * 4;
            let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
            Some(Buffer::new(context, "intersection calls", bytes, usage, MemoryLocation::CpuToGpu)?)
        } else {
            None
        };
        let readback = Buffer::new(
            context,
            "pixel read-back",
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(Self {
            context: context.clone(),
            output,
            width,
            height,
            written,
            unused,
            accumulation,
            intersection_calls,
            readback,
            descriptors: TraceDescriptors::new(context, pipeline)?,
            timestamps: TimestampPool::around_trace(context)?,
        })
    }

    /// Points the descriptors at `scene` and writes its camera to the uniforms.
    fn bind(&mut self, scene: &PreparedScene) {
        let (pixels, display) = match self.output {
            PixelOutput::Aovs => (&self.written, &self.unused),
            PixelOutput::Display | PixelOutput::DisplayBgra => (&self.unused, &self.written),
        };
        let mut storage = vec![
            StorageRange::whole(BINDING_LIGHTS, &scene.lights),
            StorageRange::whole(BINDING_PIXELS, pixels),
            StorageRange::whole(BINDING_DISPLAY_PIXELS, display),
            StorageRange::whole(BINDING_ACCUMULATION, self.accumulation.as_ref().unwrap_or(&self.unused)),
        ];
        if let Some(calls) = &mut self.intersection_calls {
            calls.write(&vec![0; calls.size as usize]);
            storage.push(StorageRange::whole(BINDING_INTERSECTION_CALLS, calls));
        }
        self.descriptors.write(scene, &storage);
    }
}

/// The image in `pixels`; `with_albedo` where the path integrator left each hit's albedo in
/// half floats in `ids.zw` (path_tracer.glsl).
fn image_from_pixels(width: u32, height: u32, pixels: &[PixelRecord], with_albedo: bool) -> RenderedImage {
    let albedo = |p: &PixelRecord| unpack_half2x16(p.ids[2]).extend(unpack_half2x16(p.ids[3]).x);
    let hit = |p: &PixelRecord| p.normal_depth[3] >= 0.0;
    RenderedImage {
        width,
        height,
        color: pixels.iter().map(|p| Vec3::from_slice(&p.color[..3])).collect(),
        depth: pixels.iter().map(|p| if hit(p) { p.normal_depth[3] } else { f32::INFINITY }).collect(),
        normal: pixels
            .iter()
            .map(|p| if hit(p) { Vec3::from_slice(&p.normal_depth[..3]) } else { Vec3::ZERO })
            .collect(),
        instance_id: pixels.iter().map(|p| if hit(p) { p.ids[0] } else { RenderedImage::MISS }).collect(),
        primitive_id: pixels.iter().map(|p| if hit(p) { p.ids[1] } else { RenderedImage::MISS }).collect(),
        albedo: with_albedo
            .then(|| pixels.iter().map(|p| if hit(p) { albedo(p) } else { Vec3::ZERO }).collect()),
    }
}
