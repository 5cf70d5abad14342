//! Counting every ray a frame traces (primary, shadow and reflection) on the GPU, with the
//! `COUNT_RAYS` variant of the ray generation shader; the timed pipeline does not count.

use pointray_scene::RenderSettings;

use crate::binding_table::ShaderBindingTable;
use crate::error::VulkanError;
use crate::gpu_records::PixelRecord;
use crate::pipeline::RayTracingPipeline;
use crate::prepared_scene::PreparedScene;
use crate::renderer::VulkanRenderer;
use crate::shaders;
use crate::trace::{create_resources, record, validate};

impl VulkanRenderer {
    /// How many rays one frame of `scene` traces with `settings`, counted per pixel on the GPU
    /// and summed here. Builds the counting pipeline for this call only.
    pub fn count_rays(&self, scene: &PreparedScene, settings: &RenderSettings) -> Result<u64, VulkanError> {
        self.ensure_prepared_here(scene)?;
        validate(settings, &self.context)?;
        let pipeline = RayTracingPipeline::with_raygen(&self.context, shaders::PRIMARY_COUNTING_RGEN)?;
        let table = ShaderBindingTable::new(&self.context, &pipeline)?;
        let resources = create_resources(&self.context, &pipeline, scene, settings)?;
        self.context.submit_and_wait("counting rays", |command| {
            record(&self.context, command, &pipeline, &table, &resources, settings)
        })?;
        let pixels: Vec<PixelRecord> = bytemuck::pod_collect_to_vec(resources.readback.read());
        Ok(pixels.iter().map(|pixel| u64::from(pixel.ids[2])).sum())
    }
}
