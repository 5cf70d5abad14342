//! Counting every ray a frame traces (primary, shadow and reflection) on the GPU, with the
//! `COUNT_RAYS` variant of the ray generation shader; the timed pipeline does not count.

use pointray_scene::{Integrator, RenderSettings};

use crate::binding_table::ShaderBindingTable;
use crate::error::VulkanError;
use crate::gpu_records::PixelRecord;
use crate::pipeline::RayTracingPipeline;
use crate::prepared_scene::PreparedScene;
use crate::renderer::VulkanRenderer;
use crate::shaders;
use crate::trace::trace_into;
use crate::trace_target::{PixelOutput, TraceTarget};

impl VulkanRenderer {
    /// How many rays one frame of `scene` traces with `settings`, counted per pixel on the GPU
    /// and summed here. Builds the counting pipeline of `settings.integrator` for this call only.
    pub fn count_rays(&self, scene: &PreparedScene, settings: &RenderSettings) -> Result<u64, VulkanError> {
        self.ensure_prepared_here(scene)?;
        let raygen = match settings.integrator {
            Integrator::Whitted => shaders::PRIMARY_COUNTING_RGEN,
            Integrator::Path => shaders::PATH_COUNTING_RGEN,
        };
        let pipeline = RayTracingPipeline::with_raygen(&self.context, raygen, settings.integrator)?;
        let table = ShaderBindingTable::new(&self.context, &pipeline)?;
        let mut target = TraceTarget::new(PixelOutput::Aovs);
        trace_into(&self.context, &pipeline, &table, scene, settings, &mut target)?;
        let pixels: Vec<PixelRecord> = bytemuck::pod_collect_to_vec(target.read_back()?);
        Ok(pixels.iter().map(|pixel| u64::from(pixel.ids[2])).sum())
    }
}
