//! The ray-tracing pipeline: ray generation, two miss shaders (background, shadow) and three
//! hit groups (0: patch intersection + closest hit, 1: triangle closest hit, 2: the patch
//! group for boxes of several patches each), with the
//! descriptor layout of `shaders/bindings.glsl`. The benchmark's counting pipeline has one
//! binding more, the intersection calls per pixel that `patch.rint` counts with `COUNT_RAYS`.

use std::sync::Arc;

use ash::vk;
use pointray_scene::Integrator;

use crate::context::GpuContext;
use crate::error::{VkContext, VulkanError};
use crate::gpu_records::TraceSettings;
use crate::shaders;
use pointray_scene::HotRecords;

pub(crate) const BINDING_TLAS: u32 = 0;
pub(crate) const BINDING_FRAME: u32 = 1;
pub(crate) const BINDING_OBJECTS: u32 = 2;
pub(crate) const BINDING_LIGHTS: u32 = 3;
pub(crate) const BINDING_PIXELS: u32 = 4;
pub(crate) const BINDING_DISPLAY_PIXELS: u32 = 5;
pub(crate) const BINDING_ACCUMULATION: u32 = 6;
pub(crate) const BINDING_RAY_LIST: u32 = 7;
pub(crate) const BINDING_RAY_HITS: u32 = 8;
pub(crate) const BINDING_RAY_POSES: u32 = 9;
/// The counting pipeline's intersection calls per pixel (`patch.rint` with `COUNT_RAYS`); the
/// timed pipeline's layout has no such binding.
pub(crate) const BINDING_INTERSECTION_CALLS: u32 = 10;
/// The storage buffers among the timed pipeline's bindings: the objects, lights, the three
/// pixel outputs and the ray list's three.
const STORAGE_BINDING_COUNT: u32 = 8;

/// Shader groups in pipeline order; the shader binding table follows it.
pub(crate) const GROUP_RAYGEN: u32 = 0;
pub(crate) const GROUP_MISS_FIRST: u32 = 1;
pub(crate) const MISS_GROUP_COUNT: u32 = 2;
pub(crate) const GROUP_HIT_FIRST: u32 = 3;
pub(crate) const HIT_GROUP_COUNT: u32 = 4;
/// The instance SBT offsets (`instanceShaderBindingTableRecordOffset`).
pub(crate) const HIT_GROUP_PATCHES: u32 = 0;
pub(crate) const HIT_GROUP_TRIANGLES: u32 = 1;
pub(crate) const HIT_GROUP_PATCH_GROUPS: u32 = 2;
pub(crate) const HIT_GROUP_UNPACKED_PATCHES: u32 = 3;

/// The hit group of a point set's tile whose boxes each bound `patches_per_box` patches, with
/// hot records in the form `hot_records`. Boxes of several patches read packed records only:
/// a scene takes them to save memory, which unpacked records spend.
pub(crate) fn patch_hit_group(patches_per_box: u32, hot_records: HotRecords) -> u32 {
    match (patches_per_box > 1, hot_records) {
        (true, _) => HIT_GROUP_PATCH_GROUPS,
        (false, HotRecords::Packed) => HIT_GROUP_PATCHES,
        (false, HotRecords::Unpacked) => HIT_GROUP_UNPACKED_PATCHES,
    }
}

pub(crate) struct RayTracingPipeline {
    context: Arc<GpuContext>,
    pub(crate) set_layout: vk::DescriptorSetLayout,
    pub(crate) layout: vk::PipelineLayout,
    pub(crate) pipeline: vk::Pipeline,
    /// The integrator its ray generation shader implements.
    pub(crate) integrator: Integrator,
    /// Its intersection shader counts its calls at `BINDING_INTERSECTION_CALLS`.
    pub(crate) counts_intersections: bool,
}

impl RayTracingPipeline {
    /// The pipeline with one of the ray generation shaders of `shaders.rs`, which implements
    /// `integrator`.
    pub(crate) fn with_raygen(
        context: &Arc<GpuContext>,
        raygen: &[u8],
        integrator: Integrator,
    ) -> Result<Self, VulkanError> {
        Self::new(context, raygen, integrator, false)
    }

    /// As `with_raygen`, with the intersection shader that counts its calls per pixel: for a
    /// `COUNT_RAYS` ray generation shader.
    pub(crate) fn counting(
        context: &Arc<GpuContext>,
        raygen: &[u8],
        integrator: Integrator,
    ) -> Result<Self, VulkanError> {
        Self::new(context, raygen, integrator, true)
    }

    fn new(
        context: &Arc<GpuContext>,
        raygen: &[u8],
        integrator: Integrator,
        counts_intersections: bool,
    ) -> Result<Self, VulkanError> {
        let device = &context.device;
        let set_layout = create_set_layout(device, counts_intersections)?;
        let mut owned = Self {
            context: context.clone(),
            set_layout,
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
            integrator,
            counts_intersections,
        };
        let push_constants = [vk::PushConstantRange::default()
            .stage_flags(all_ray_stages())
            .size(std::mem::size_of::<TraceSettings>() as u32)];
        let set_layouts = [set_layout];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_layouts)
            .push_constant_ranges(&push_constants);
        // SAFETY: the device is alive; handles are destroyed in Drop.
        owned.layout =
            unsafe { device.create_pipeline_layout(&info, None) }.during("creating the pipeline layout")?;
        let intersections = if counts_intersections {
            [
                shaders::PATCH_COUNTING_RINT,
                shaders::PATCH_GROUPS_COUNTING_RINT,
                shaders::PATCH_UNPACKED_COUNTING_RINT,
            ]
        } else {
            [shaders::PATCH_RINT, shaders::PATCH_GROUPS_RINT, shaders::PATCH_UNPACKED_RINT]
        };
        owned.pipeline = create_pipeline(context, owned.layout, raygen, intersections)?;
        Ok(owned)
    }

    /// The storage buffers its set layout binds.
    pub(crate) fn storage_binding_count(&self) -> u32 {
        STORAGE_BINDING_COUNT + u32::from(self.counts_intersections)
    }
}

impl Drop for RayTracingPipeline {
    fn drop(&mut self) {
        let device = &self.context.device;
        // SAFETY: no trace using the pipeline is pending; null handles are ignored.
        unsafe {
            device.destroy_pipeline(self.pipeline, None);
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}

pub(crate) fn all_ray_stages() -> vk::ShaderStageFlags {
    vk::ShaderStageFlags::RAYGEN_KHR
        | vk::ShaderStageFlags::MISS_KHR
        | vk::ShaderStageFlags::INTERSECTION_KHR
        | vk::ShaderStageFlags::CLOSEST_HIT_KHR
}

fn create_set_layout(
    device: &ash::Device,
    counts_intersections: bool,
) -> Result<vk::DescriptorSetLayout, VulkanError> {
    let binding = |index, ty, stages| {
        vk::DescriptorSetLayoutBinding::default()
            .binding(index)
            .descriptor_type(ty)
            .descriptor_count(1)
            .stage_flags(stages)
    };
    let raygen = vk::ShaderStageFlags::RAYGEN_KHR;
    let mut bindings = vec![
        binding(BINDING_TLAS, vk::DescriptorType::ACCELERATION_STRUCTURE_KHR, raygen),
        binding(BINDING_FRAME, vk::DescriptorType::UNIFORM_BUFFER, raygen | vk::ShaderStageFlags::MISS_KHR),
        binding(BINDING_OBJECTS, vk::DescriptorType::STORAGE_BUFFER, all_ray_stages()),
        binding(BINDING_LIGHTS, vk::DescriptorType::STORAGE_BUFFER, raygen),
        binding(BINDING_PIXELS, vk::DescriptorType::STORAGE_BUFFER, raygen),
        binding(BINDING_DISPLAY_PIXELS, vk::DescriptorType::STORAGE_BUFFER, raygen),
        binding(BINDING_ACCUMULATION, vk::DescriptorType::STORAGE_BUFFER, raygen),
        binding(BINDING_RAY_LIST, vk::DescriptorType::STORAGE_BUFFER, raygen),
        binding(BINDING_RAY_HITS, vk::DescriptorType::STORAGE_BUFFER, raygen),
        binding(BINDING_RAY_POSES, vk::DescriptorType::STORAGE_BUFFER, raygen),
    ];
    if counts_intersections {
        let intersection = vk::ShaderStageFlags::INTERSECTION_KHR;
        bindings.push(binding(BINDING_INTERSECTION_CALLS, vk::DescriptorType::STORAGE_BUFFER, intersection));
    }
    let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
    // SAFETY: the device is alive.
    unsafe { device.create_descriptor_set_layout(&info, None) }.during("creating the descriptor set layout")
}

/// Shader modules, destroyed once the pipeline holds them.
struct Modules<'a> {
    device: &'a ash::Device,
    handles: Vec<vk::ShaderModule>,
}

impl Modules<'_> {
    fn add(&mut self, spirv: &[u8]) -> Result<vk::ShaderModule, VulkanError> {
        let words = shaders::words(spirv);
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        // SAFETY: the SPIR-V was produced by glslang in build.rs.
        let module =
            unsafe { self.device.create_shader_module(&info, None) }.during("creating a shader module")?;
        self.handles.push(module);
        Ok(module)
    }
}

impl Drop for Modules<'_> {
    fn drop(&mut self) {
        for &module in &self.handles {
            // SAFETY: pipeline creation has finished with the modules.
            unsafe { self.device.destroy_shader_module(module, None) };
        }
    }
}

fn create_pipeline(
    context: &GpuContext,
    layout: vk::PipelineLayout,
    raygen: &[u8],
    [intersection, group_intersection, unpacked_intersection]: [&[u8]; 3],
) -> Result<vk::Pipeline, VulkanError> {
    let mut modules = Modules { device: &context.device, handles: Vec::new() };
    let stage = |stage, module| {
        vk::PipelineShaderStageCreateInfo::default().stage(stage).module(module).name(c"main")
    };
    let stages = [
        stage(vk::ShaderStageFlags::RAYGEN_KHR, modules.add(raygen)?),
        stage(vk::ShaderStageFlags::MISS_KHR, modules.add(shaders::BACKGROUND_RMISS)?),
        stage(vk::ShaderStageFlags::MISS_KHR, modules.add(shaders::SHADOW_RMISS)?),
        stage(vk::ShaderStageFlags::INTERSECTION_KHR, modules.add(intersection)?),
        stage(vk::ShaderStageFlags::CLOSEST_HIT_KHR, modules.add(shaders::PATCH_RCHIT)?),
        stage(vk::ShaderStageFlags::CLOSEST_HIT_KHR, modules.add(shaders::TRIANGLE_RCHIT)?),
        stage(vk::ShaderStageFlags::INTERSECTION_KHR, modules.add(group_intersection)?),
        stage(vk::ShaderStageFlags::CLOSEST_HIT_KHR, modules.add(shaders::PATCH_GROUPS_RCHIT)?),
        stage(vk::ShaderStageFlags::INTERSECTION_KHR, modules.add(unpacked_intersection)?),
        stage(vk::ShaderStageFlags::CLOSEST_HIT_KHR, modules.add(shaders::PATCH_UNPACKED_RCHIT)?),
    ];
    let group = |ty| {
        vk::RayTracingShaderGroupCreateInfoKHR::default()
            .ty(ty)
            .general_shader(vk::SHADER_UNUSED_KHR)
            .closest_hit_shader(vk::SHADER_UNUSED_KHR)
            .any_hit_shader(vk::SHADER_UNUSED_KHR)
            .intersection_shader(vk::SHADER_UNUSED_KHR)
    };
    let general = vk::RayTracingShaderGroupTypeKHR::GENERAL;
    let groups = [
        group(general).general_shader(0),
        group(general).general_shader(1),
        group(general).general_shader(2),
        group(vk::RayTracingShaderGroupTypeKHR::PROCEDURAL_HIT_GROUP)
            .intersection_shader(3)
            .closest_hit_shader(4),
        group(vk::RayTracingShaderGroupTypeKHR::TRIANGLES_HIT_GROUP).closest_hit_shader(5),
        group(vk::RayTracingShaderGroupTypeKHR::PROCEDURAL_HIT_GROUP)
            .intersection_shader(6)
            .closest_hit_shader(7),
        group(vk::RayTracingShaderGroupTypeKHR::PROCEDURAL_HIT_GROUP)
            .intersection_shader(8)
            .closest_hit_shader(9),
    ];
    // Ray generation shades and traces every bounce itself; hit shaders trace nothing.
    let info = vk::RayTracingPipelineCreateInfoKHR::default()
        .stages(&stages)
        .groups(&groups)
        .max_pipeline_ray_recursion_depth(1)
        .layout(layout);
    // SAFETY: every array the create info points to outlives the call.
    let pipelines = unsafe {
        context.ray_tracing.create_ray_tracing_pipelines(
            vk::DeferredOperationKHR::null(),
            vk::PipelineCache::null(),
            &[info],
            None,
        )
    };
    pipelines
        .map(|p| p[0])
        .map_err(|(_, result)| VulkanError::from_vk("creating the ray-tracing pipeline", result))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spirv_reflection::Reflection;

    #[test]
    fn every_binding_has_the_compiled_shaders_number() {
        let probe = Reflection::of(crate::shaders::INTERFACE_PROBE_RGEN);
        for (glsl_name, binding) in [
            ("scene_tlas", BINDING_TLAS),
            ("FrameUniforms", BINDING_FRAME),
            ("Objects", BINDING_OBJECTS),
            ("Lights", BINDING_LIGHTS),
            ("Pixels", BINDING_PIXELS),
            ("DisplayPixels", BINDING_DISPLAY_PIXELS),
            ("Accumulation", BINDING_ACCUMULATION),
            ("RayList", BINDING_RAY_LIST),
            ("RayHits", BINDING_RAY_HITS),
            ("RayPoses", BINDING_RAY_POSES),
        ] {
            assert_eq!(probe.binding_of(glsl_name), (0, binding), "{glsl_name}: (set, binding)");
        }
    }

    #[test]
    fn only_the_counting_intersection_shader_binds_its_calls() {
        let counting = Reflection::of(crate::shaders::PATCH_COUNTING_RINT);
        assert_eq!(counting.binding_of("IntersectionCalls"), (0, BINDING_INTERSECTION_CALLS));
        let grouped = Reflection::of(crate::shaders::PATCH_GROUPS_COUNTING_RINT);
        assert_eq!(grouped.binding_of("IntersectionCalls"), (0, BINDING_INTERSECTION_CALLS));
        for timed in [crate::shaders::PATCH_RINT, crate::shaders::PATCH_GROUPS_RINT] {
            let timed = Reflection::of(timed);
            assert!(!timed.has_binding("IntersectionCalls"), "the timed pipeline binds no counter");
        }
    }
}
