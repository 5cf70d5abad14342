//! Counting every ray a frame traces (primary, shadow and reflection) and every call of the
//! patch intersection shader on the GPU, with the `COUNT_RAYS` variants of the ray generation
//! and intersection shaders; the timed pipeline does not count.

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

/// What one frame traced, counted on the GPU.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Every ray traced: primary, shadow and reflection (or path segments).
    pub rays: u64,
    /// Every call of the patch intersection shader, by any of those rays: one per box a ray
    /// enters, as the traversal reports them.
    pub intersection_calls: u64,
}

impl RayCounts {
    /// Intersection-shader calls per traced ray; 0 when nothing was traced.
    pub fn intersection_calls_per_ray(&self) -> f64 {
        if self.rays == 0 { 0.0 } else { self.intersection_calls as f64 / self.rays as f64 }
    }
}

impl VulkanRenderer {
    /// How many rays and intersection-shader calls one frame of `scene` traces with
    /// `settings`, counted per pixel on the GPU and summed here. Builds the counting pipeline
    /// of `settings.integrator` for this call only.
    pub fn count_rays(
        &self,
        scene: &PreparedScene,
        settings: &RenderSettings,
    ) -> Result<RayCounts, VulkanError> {
        self.ensure_prepared_here(scene)?;
        let raygen = match settings.integrator {
            Integrator::Whitted => shaders::PRIMARY_COUNTING_RGEN,
            Integrator::Path => shaders::PATH_COUNTING_RGEN,
        };
        let pipeline = RayTracingPipeline::counting(&self.context, raygen, settings.integrator)?;
        let table = ShaderBindingTable::new(&self.context, &pipeline)?;
        let mut target = TraceTarget::new(PixelOutput::Aovs);
        trace_into(&self.context, &pipeline, &table, scene, settings, &mut target)?;
        let pixels: Vec<PixelRecord> = bytemuck::pod_collect_to_vec(target.read_back()?);
        Ok(RayCounts {
            rays: pixels.iter().map(|pixel| u64::from(pixel.ids[2])).sum(),
            intersection_calls: target
                .intersection_calls()
                .expect("a counting pipeline's target counts them"),
        })
    }
}
