//! Global memory barriers: every dependency this renderer records is one of these.

use ash::vk;

/// Makes `src_access` writes in `src_stage` visible to `dst_access` in `dst_stage`.
///
/// # Safety
/// `command` is in the recording state.
pub(crate) unsafe fn record_memory_barrier(
    device: &ash::Device,
    command: vk::CommandBuffer,
    (src_stage, src_access): (vk::PipelineStageFlags, vk::AccessFlags),
    (dst_stage, dst_access): (vk::PipelineStageFlags, vk::AccessFlags),
) {
    let barrier = vk::MemoryBarrier::default().src_access_mask(src_access).dst_access_mask(dst_access);
    // SAFETY: the caller's contract.
    unsafe {
        device.cmd_pipeline_barrier(
            command,
            src_stage,
            dst_stage,
            vk::DependencyFlags::empty(),
            &[barrier],
            &[],
            &[],
        )
    };
}
