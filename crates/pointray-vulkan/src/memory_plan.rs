//! What a scene will take on the GPU, worked out from the device's build-size queries before
//! anything is uploaded, so that a scene over its memory budget is refused with the numbers
//! instead of failing halfway through the upload.

use pointray_io::TriangleMesh;
use pointray_scene::{Geometry, Scene};

use crate::acceleration::{aabb_input, build_sizes, instance_input, triangle_input};
use crate::context::GpuContext;
use crate::error::VulkanError;
use crate::gpu_records::ObjectRecord;
use crate::patch_upload::{box_bytes, patch_tiles, record_bytes};
use crate::prepared_scene::SceneLayout;

/// Bytes of one TLAS instance record (`VkAccelerationStructureInstanceKHR`).
const INSTANCE_BYTES: u64 = 64;

/// A scene's GPU memory, planned.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct MemoryNeed {
    /// What stays while the scene is traced: records, meshes, bottom levels before
    /// compaction (an upper bound), the top level and the object records.
    pub(crate) kept: u64,
    /// What the largest build needs besides: an object's boxes or mesh and the scratch.
    pub(crate) building: u64,
    /// Bottom levels: one per mesh and per tile of a point set.
    pub(crate) bottom_levels: usize,
}

impl MemoryNeed {
    fn add(&mut self, kept: u64, building: u64, bottom_levels: usize) {
        self.kept += kept;
        self.building = self.building.max(building);
        self.bottom_levels += bottom_levels;
    }

    pub(crate) fn total(&self) -> u64 {
        self.kept + self.building
    }
}

pub(crate) fn plan(context: &GpuContext, scene: &Scene, layout: SceneLayout, max_tile: u32) -> MemoryNeed {
    let mut need = MemoryNeed::default();
    for object in &scene.objects {
        match &object.geometry {
            Geometry::Patches(patches) => {
                let (mut structures, mut scratch) = (0, 0);
                let tiles = patch_tiles(patches, max_tile);
                for tile in &tiles {
                    let (size, tile_scratch) =
                        build_sizes(context, &aabb_input(0, tile.len() as u32, layout.blas));
                    structures += size;
                    scratch = scratch.max(tile_scratch);
                }
                let records = record_bytes(patches, &object.material, layout.buffers);
                need.add(records + structures, box_bytes(patches) + scratch, tiles.len());
            }
            Geometry::Mesh(mesh) if mesh.triangles.is_empty() => need.add(mesh_bytes(mesh), 0, 0),
            Geometry::Mesh(mesh) => {
                let input = triangle_input(0, mesh.positions.len() as u32, 0, mesh.triangles.len() as u32);
                let (size, scratch) = build_sizes(context, &input);
                need.add(mesh_bytes(mesh) + size, scratch, 1);
            }
        }
    }
    let instances = need.bottom_levels as u64;
    let (tlas, scratch) = build_sizes(context, &instance_input(0, instances as u32));
    let records = instances.max(1) * size_of::<ObjectRecord>() as u64;
    need.add(tlas + records, instances * INSTANCE_BYTES + scratch, 0);
    need
}

/// Vertices as vec4 and u32 indices, as the trace reads them.
fn mesh_bytes(mesh: &TriangleMesh) -> u64 {
    mesh.positions.len() as u64 * 16 + mesh.triangles.len() as u64 * 12
}

/// The budget a scene must fit: the caller's, else the device's largest device-local heap.
pub(crate) fn check_budget(
    context: &GpuContext,
    need: &MemoryNeed,
    budget: Option<u64>,
) -> Result<(), VulkanError> {
    let (budget, source) = match budget {
        Some(bytes) => (bytes, "the GPU memory budget".to_string()),
        None => {
            (context.info.device_local_bytes, format!("the device-local memory of {}", context.info.name))
        }
    };
    if need.total() <= budget || budget == 0 {
        return Ok(());
    }
    let mib = |bytes: u64| bytes as f64 / (1 << 20) as f64;
    Err(VulkanError::OverBudget(format!(
        "the scene needs {:.1} MiB of GPU memory ({:.1} MiB kept: patch records, meshes and {} acceleration \
         structures; {:.1} MiB more while building), over {source} of {:.1} MiB; render fewer points or \
         use the CPU backend",
        mib(need.total()),
        mib(need.kept),
        need.bottom_levels + 1,
        mib(need.building),
        mib(budget)
    )))
}
