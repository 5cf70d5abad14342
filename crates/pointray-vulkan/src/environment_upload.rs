//! The background's environment map on the GPU: its texels and its sampling distribution,
//! read by address through the frame uniforms (`bindings.glsl`, `environment_map.glsl`).

use std::sync::Arc;

use pointray_kernels::EnvironmentMap;

use crate::buffer::{Buffer, storage_usage};
use crate::context::GpuContext;
use crate::error::VulkanError;

pub(crate) struct EnvironmentBuffers {
    pub(crate) texels: Buffer,
    pub(crate) distribution: Buffer,
}

impl EnvironmentBuffers {
    pub(crate) fn upload(context: &Arc<GpuContext>, map: &EnvironmentMap) -> Result<Self, VulkanError> {
        let texels = bytemuck::cast_slice(map.texels());
        let distribution = bytemuck::cast_slice(map.distribution());
        Ok(Self {
            texels: Buffer::device_with_data(context, "environment map texels", texels, storage_usage())?,
            distribution: Buffer::device_with_data(
                context,
                "environment map distribution",
                distribution,
                storage_usage(),
            )?,
        })
    }

    pub(crate) fn bytes(&self) -> u64 {
        self.texels.size + self.distribution.size
    }
}
