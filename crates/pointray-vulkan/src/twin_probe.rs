//! Runs a twin probe (`shaders/twins/NAME.comp`) over a batch of cases on the device, so the
//! GLSL twins can be held against their Rust twins (`twin_agreement.rs`). Case `i` reads
//! `inputs_per_case` vec4s and writes `outputs_per_case` vec4s (`twin_io.glsl`).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::barrier::record_memory_barrier;
use crate::buffer::Buffer;
use crate::context::GpuContext;
use crate::device::{DeviceOptions, DeviceSelector};
use crate::error::{VkContext, VulkanError};

macro_rules! twin_probe {
    ($name:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/twins/", $name, ".comp.spv"))
    };
}
pub(crate) const QUADRATIC_ROOTS: &[u8] = twin_probe!("quadratic_roots");
pub(crate) const INTERSECT_PATCH: &[u8] = twin_probe!("intersect_patch");
pub(crate) const SHADING: &[u8] = twin_probe!("shading");
pub(crate) const CAMERA_RAY: &[u8] = twin_probe!("camera_ray");
pub(crate) const INTERPOLATE_COLOR: &[u8] = twin_probe!("interpolate_color");
pub(crate) const PATH_SAMPLING: &[u8] = twin_probe!("path_sampling");
pub(crate) const PATH_DRAWS: &[u8] = twin_probe!("path_draws");
pub(crate) const RECORD_ADDRESS: &[u8] = twin_probe!("record_address");

const WORKGROUP_SIZE: u32 = 64;

/// A validated context on the best device; `None` (after a note) without one, except under
/// CI (`CI=true`), where that fails the test.
pub(crate) fn probe_context() -> Option<Arc<GpuContext>> {
    match GpuContext::new(&DeviceSelector::Auto, DeviceOptions::VALIDATED, None) {
        Ok(context) => Some(Arc::new(context)),
        Err(error) if error.is_no_device() => {
            assert!(
                std::env::var("CI").as_deref() != Ok("true"),
                "CI=true but no usable Vulkan device: {error}"
            );
            eprintln!("note: skipping, no usable Vulkan device: {error}");
            None
        }
        Err(error) => panic!("creating the context failed: {error}"),
    }
}

/// The outputs of `probe` for `inputs` (`inputs.len() / inputs_per_case` cases).
pub(crate) fn run_probe(
    context: &Arc<GpuContext>,
    probe: &[u8],
    inputs: &[[f32; 4]],
    (inputs_per_case, outputs_per_case): (usize, usize),
) -> Result<Vec<[f32; 4]>, VulkanError> {
    // A probe may read one shared vec4 after the cases (`interpolate_color.comp`).
    let cases = inputs.len() / inputs_per_case;
    let input = Buffer::host_with_data(
        context,
        "twin inputs",
        bytemuck::cast_slice(inputs),
        vk::BufferUsageFlags::STORAGE_BUFFER,
    )?;
    let output_size = (cases * outputs_per_case * 16) as u64;
    let output = Buffer::new(
        context,
        "twin outputs",
        output_size,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuToCpu,
    )?;
    let pipeline = ProbePipeline::new(context, probe)?;
    pipeline.dispatch(&input, &output, cases as u32)?;
    let outputs: &[[f32; 4]] = bytemuck::cast_slice(&output.read()[..output_size as usize]);
    Ok(outputs.to_vec())
}

/// A compute pipeline with two storage buffers and the case count, freed on drop.
struct ProbePipeline {
    context: Arc<GpuContext>,
    module: vk::ShaderModule,
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
    pool: vk::DescriptorPool,
}

impl ProbePipeline {
    fn new(context: &Arc<GpuContext>, probe: &[u8]) -> Result<Self, VulkanError> {
        let device = &context.device;
        let words = crate::shaders::words(probe);
        let storage = |binding| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE)
        };
        let bindings = [storage(0), storage(1)];
        let push = [vk::PushConstantRange::default().stage_flags(vk::ShaderStageFlags::COMPUTE).size(4)];
        let sizes =
            [vk::DescriptorPoolSize::default().ty(vk::DescriptorType::STORAGE_BUFFER).descriptor_count(2)];
        // SAFETY: the device is alive; every object made here is destroyed in Drop (the
        // handles start null, and destroying a null handle is a no-op).
        unsafe {
            let mut made = Self {
                context: context.clone(),
                module: vk::ShaderModule::null(),
                set_layout: vk::DescriptorSetLayout::null(),
                layout: vk::PipelineLayout::null(),
                pipeline: vk::Pipeline::null(),
                pool: vk::DescriptorPool::null(),
            };
            let during = "creating a twin probe";
            made.module = device
                .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&words), None)
                .during(during)?;
            made.set_layout = device
                .create_descriptor_set_layout(
                    &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
                    None,
                )
                .during(during)?;
            let set_layouts = [made.set_layout];
            let layout_info =
                vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts).push_constant_ranges(&push);
            made.layout = device.create_pipeline_layout(&layout_info, None).during(during)?;
            let stage = vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::COMPUTE)
                .module(made.module)
                .name(c"main");
            let info = vk::ComputePipelineCreateInfo::default().stage(stage).layout(made.layout);
            made.pipeline = device
                .create_compute_pipelines(vk::PipelineCache::null(), &[info], None)
                .map_err(|(_, e)| e)
                .during(during)?[0];
            let pool_info = vk::DescriptorPoolCreateInfo::default().max_sets(1).pool_sizes(&sizes);
            made.pool = device.create_descriptor_pool(&pool_info, None).during(during)?;
            Ok(made)
        }
    }

    fn dispatch(&self, input: &Buffer, output: &Buffer, cases: u32) -> Result<(), VulkanError> {
        let device = &self.context.device;
        let set_layouts = [self.set_layout];
        let allocate =
            vk::DescriptorSetAllocateInfo::default().descriptor_pool(self.pool).set_layouts(&set_layouts);
        // SAFETY: the pool has room for this one set; the buffers outlive the submission,
        // which is waited on.
        unsafe {
            let set = device.allocate_descriptor_sets(&allocate).during("allocating a twin probe's set")?[0];
            let infos = [input, output]
                .map(|b| [vk::DescriptorBufferInfo::default().buffer(b.handle).range(vk::WHOLE_SIZE)]);
            let writes: Vec<vk::WriteDescriptorSet> = infos
                .iter()
                .enumerate()
                .map(|(binding, info)| {
                    vk::WriteDescriptorSet::default()
                        .dst_set(set)
                        .dst_binding(binding as u32)
                        .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                        .buffer_info(info)
                })
                .collect();
            device.update_descriptor_sets(&writes, &[]);
            self.context.submit_and_wait("running a twin probe", |command| {
                device.cmd_bind_pipeline(command, vk::PipelineBindPoint::COMPUTE, self.pipeline);
                device.cmd_bind_descriptor_sets(
                    command,
                    vk::PipelineBindPoint::COMPUTE,
                    self.layout,
                    0,
                    &[set],
                    &[],
                );
                device.cmd_push_constants(
                    command,
                    self.layout,
                    vk::ShaderStageFlags::COMPUTE,
                    0,
                    &cases.to_le_bytes(),
                );
                device.cmd_dispatch(command, cases.div_ceil(WORKGROUP_SIZE), 1, 1);
                record_memory_barrier(
                    device,
                    command,
                    (vk::PipelineStageFlags::COMPUTE_SHADER, vk::AccessFlags::SHADER_WRITE),
                    (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
                );
            })
        }
    }
}

impl Drop for ProbePipeline {
    fn drop(&mut self) {
        let device = &self.context.device;
        // SAFETY: `dispatch` waited for the GPU; nothing else uses these objects.
        unsafe {
            device.destroy_descriptor_pool(self.pool, None);
            device.destroy_pipeline(self.pipeline, None);
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
            device.destroy_shader_module(self.module, None);
        }
    }
}
