//! A light that the path integrator draws from a table (the background's environment map,
//! the emissive triangles): its records and its sampling distribution on the GPU, read by
//! address through the frame uniforms (`bindings.glsl`).

use std::sync::Arc;

use pointray_kernels::{EmissiveTriangles, EnvironmentMap};

use crate::buffer::{Buffer, storage_usage};
use crate::context::GpuContext;
use crate::error::VulkanError;

pub(crate) struct LightTable {
    pub(crate) records: Buffer,
    pub(crate) distribution: Buffer,
}

impl LightTable {
    pub(crate) fn environment(context: &Arc<GpuContext>, map: &EnvironmentMap) -> Result<Self, VulkanError> {
        Self::upload(
            context,
            ["environment map texels", "environment map distribution"],
            map.texels(),
            map.distribution(),
        )
    }

    /// `None` without emissive triangles.
    pub(crate) fn emissive(
        context: &Arc<GpuContext>,
        triangles: &EmissiveTriangles,
    ) -> Result<Option<Self>, VulkanError> {
        if triangles.is_empty() {
            return Ok(None);
        }
        let names = ["emissive triangles", "emissive triangle distribution"];
        Self::upload(context, names, triangles.records(), triangles.distribution()).map(Some)
    }

    fn upload(
        context: &Arc<GpuContext>,
        [records_name, distribution_name]: [&'static str; 2],
        records: &[[f32; 4]],
        distribution: &[f32],
    ) -> Result<Self, VulkanError> {
        let records = bytemuck::cast_slice(records);
        let distribution = bytemuck::cast_slice(distribution);
        Ok(Self {
            records: Buffer::device_with_data(context, records_name, records, storage_usage())?,
            distribution: Buffer::device_with_data(
                context,
                distribution_name,
                distribution,
                storage_usage(),
            )?,
        })
    }

    pub(crate) fn bytes(&self) -> u64 {
        self.records.size + self.distribution.size
    }
}
