//! The SPIR-V that `build.rs` compiled from `shaders/`.

macro_rules! spirv {
    ($name:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/", $name, ".spv"))
    };
}

pub(crate) const PRIMARY_RGEN: &[u8] = spirv!("primary.rgen");
/// `primary.rgen` with `COUNT_RAYS`: each pixel's traced rays land in its `ids.z`.
pub(crate) const PRIMARY_COUNTING_RGEN: &[u8] = spirv!("primary_counting.rgen");
/// `primary.rgen` with `REORDER_HITS`: shader execution reordering of every path segment.
pub(crate) const PRIMARY_REORDERING_RGEN: &[u8] = spirv!("primary_reordering.rgen");
/// `primary.rgen` with `PATH_TRACING`: the path integrator (`shaders/path_tracer.glsl`).
pub(crate) const PATH_RGEN: &[u8] = spirv!("path.rgen");
/// `path.rgen` with `COUNT_RAYS`.
pub(crate) const PATH_COUNTING_RGEN: &[u8] = spirv!("path_counting.rgen");
/// Casts a list of rays to their closest hits, shading nothing (`RayListTarget`).
pub(crate) const RAY_LIST_RGEN: &[u8] = spirv!("ray_list.rgen");
pub(crate) const BACKGROUND_RMISS: &[u8] = spirv!("background.rmiss");
pub(crate) const SHADOW_RMISS: &[u8] = spirv!("shadow.rmiss");
pub(crate) const PATCH_RINT: &[u8] = spirv!("patch.rint");
/// `patch.rint` with `COUNT_RAYS`: each call adds one to its pixel's `intersection_calls`.
pub(crate) const PATCH_COUNTING_RINT: &[u8] = spirv!("patch_counting.rint");
pub(crate) const PATCH_RCHIT: &[u8] = spirv!("patch.rchit");
/// `patch.rint` and `patch.rchit` with `PATCH_GROUPS`: boxes of several patches each.
pub(crate) const PATCH_GROUPS_RINT: &[u8] = spirv!("patch_groups.rint");
/// `patch_groups.rint` with `COUNT_RAYS`.
pub(crate) const PATCH_GROUPS_COUNTING_RINT: &[u8] = spirv!("patch_groups_counting.rint");
pub(crate) const PATCH_GROUPS_RCHIT: &[u8] = spirv!("patch_groups.rchit");
/// `patch.rint` and `patch.rchit` with `UNPACKED_RECORDS`: hot records unpacked at upload.
pub(crate) const PATCH_UNPACKED_RINT: &[u8] = spirv!("patch_unpacked.rint");
/// `patch_unpacked.rint` with `COUNT_RAYS`.
pub(crate) const PATCH_UNPACKED_COUNTING_RINT: &[u8] = spirv!("patch_unpacked_counting.rint");
pub(crate) const PATCH_UNPACKED_RCHIT: &[u8] = spirv!("patch_unpacked.rchit");
pub(crate) const TRIANGLE_RCHIT: &[u8] = spirv!("triangle.rchit");
/// Never run: the interface tests reflect on it.
#[cfg(test)]
pub(crate) const INTERFACE_PROBE_RGEN: &[u8] = spirv!("interface_probe.rgen");

/// SPIR-V bytes as the u32 words Vulkan wants (`include_bytes!` gives no alignment).
pub(crate) fn words(bytes: &[u8]) -> Vec<u32> {
    bytes.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect()
}
