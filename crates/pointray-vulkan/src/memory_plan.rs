//! What a scene will take on the GPU, worked out from the device's build-size queries before
//! anything is uploaded, and the ledger that holds the upload to its budget as it goes.
//!
//! A point set's bottom levels are built before its records are uploaded, one tile at a
//! time, each from its own boxes, so a build's boxes and scratch come and go beside the
//! compacted structures alone. Where the scene would not fit its budget otherwise, its
//! tiles are split until one tile's build takes no more than the records uploaded after
//! it: the peak is then about the size of the finished scene. The structures' compacted
//! sizes are known only once built, so a scene whose bound is over the budget but whose
//! floor is not is built with the ledger checking each step against the sizes it has seen.

use std::sync::Arc;

use pointray_io::TriangleMesh;
use pointray_scene::{Geometry, Scene};

use crate::acceleration::{
    AccelerationStructure, BuildInput, aabb_input, build_peak, build_sizes, instance_input, triangle_input,
};
use crate::context::GpuContext;
use crate::error::VulkanError;
use crate::gpu_records::ObjectRecord;
use crate::patch_upload::{patch_tiles, record_bytes, tile_blas, tile_box_bytes};
use crate::prepared_scene::SceneLayout;

/// Bytes of one TLAS instance record (`VkAccelerationStructureInstanceKHR`).
pub(crate) const INSTANCE_BYTES: u64 = 64;

/// The smallest tile a budget splits a point set into: below it, the structures' fixed
/// costs outweigh what a smaller build saves.
const MIN_FITTED_TILE: u32 = 1024;

/// A scene's GPU memory, planned.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct MemoryNeed {
    /// What stays while the scene is traced, besides its acceleration structures: records,
    /// meshes, the object records.
    pub(crate) buffers: u64,
    /// The acceleration structures before compaction: a bound on what they keep.
    pub(crate) structures: u64,
    /// The largest single build: its input where that goes after it (a tile's boxes, the TLAS
    /// instances), its structure before compaction and its scratch.
    pub(crate) largest_build: u64,
    /// At most what the scene holds at once: step by step in the order `prepare` takes, with
    /// every structure uncompacted.
    pub(crate) bound: u64,
    /// Bottom levels: one per mesh and per tile of a point set.
    pub(crate) bottom_levels: usize,
    /// The point sets' patches and their bottom levels' share of `structures`.
    pub(crate) patches: u64,
    pub(crate) patch_structures: u64,
}

impl MemoryNeed {
    /// What the scene keeps once built, its structures uncompacted.
    pub(crate) fn held(&self) -> u64 {
        self.buffers + self.structures
    }

    /// A buffer uploaded to stay.
    fn upload(&mut self, bytes: u64) {
        self.buffers += bytes;
        self.bound = self.bound.max(self.held());
    }

    /// A structure of `size` bytes built with `scratch` from an `input` that goes after it.
    fn build(&mut self, input: u64, size: u64, scratch: u64) {
        let transient = build_peak(input, size, scratch);
        self.largest_build = self.largest_build.max(transient);
        self.bound = self.bound.max(self.held() + transient);
        self.structures += size;
    }

    /// At least what the scene takes: its buffers once uploaded, or its largest build.
    fn floor(&self) -> u64 {
        self.buffers.max(self.largest_build)
    }
}

/// The scene's memory with point sets in tiles of at most `max_tile` patches.
pub(crate) fn plan(context: &GpuContext, scene: &Scene, layout: SceneLayout, max_tile: u32) -> MemoryNeed {
    plan_with_sizes(scene, layout, max_tile, |input| build_sizes(context, input))
}

/// `plan`, with each build's structure and scratch bytes from `sizes`.
fn plan_with_sizes(
    scene: &Scene,
    layout: SceneLayout,
    max_tile: u32,
    sizes: impl Fn(&BuildInput<'_>) -> (u64, u64),
) -> MemoryNeed {
    let mut need = MemoryNeed::default();
    for object in &scene.objects {
        match &object.geometry {
            Geometry::Patches(patches) => {
                let tiles = patch_tiles(patches, max_tile);
                need.bottom_levels += tiles.len();
                for tile in &tiles {
                    let (size, scratch) = sizes(&aabb_input(0, tile.len(), layout.blas));
                    need.build(tile_box_bytes(tile, layout.blas), size, scratch);
                    need.patch_structures += size;
                }
                need.patches += patches.len() as u64;
                need.upload(record_bytes(patches, &object.material, layout.buffers, layout.hot_records));
            }
            Geometry::Mesh(mesh) => {
                need.upload(mesh_bytes(mesh));
                if !mesh.triangles.is_empty() {
                    let input =
                        triangle_input(0, mesh.positions.len() as u32, 0, mesh.triangles.len() as u32);
                    let (size, scratch) = sizes(&input);
                    need.build(0, size, scratch);
                    need.bottom_levels += 1;
                }
            }
        }
    }
    let instances = need.bottom_levels as u64;
    let (tlas, scratch) = sizes(&instance_input(0, instances as u32));
    need.build(instances * INSTANCE_BYTES, tlas, scratch);
    need.upload(instances.max(1) * size_of::<ObjectRecord>() as u64);
    need
}

/// The largest tile, at most `max_tile` patches, that fits the scene to `budget`: `max_tile`
/// when the scene's bound fits, else halved until it does or until one tile's build is no
/// larger than the buffers (splitting further would not lower the peak below them).
pub(crate) fn fitted_tile(
    context: &GpuContext,
    scene: &Scene,
    layout: SceneLayout,
    max_tile: u32,
    budget: &GpuBudget,
) -> (u32, MemoryNeed) {
    fit_tile(max_tile, budget.bytes, |tile| plan(context, scene, layout, tile))
}

/// `fitted_tile` over the plans `plan` makes for a tile size.
fn fit_tile(max_tile: u32, budget: u64, plan: impl Fn(u32) -> MemoryNeed) -> (u32, MemoryNeed) {
    let mut tile = max_tile;
    loop {
        let need = plan(tile);
        let settled = need.bound <= budget || need.largest_build <= need.buffers;
        if settled || tile <= MIN_FITTED_TILE {
            return (tile, need);
        }
        tile = (tile / 2).max(MIN_FITTED_TILE);
    }
}

/// Patches in the sample tile whose bottom level `compacted_need` builds.
const SAMPLE_TILE_PATCHES: usize = 1 << 20;

/// What `scene`, planned as `need` in `layout`, keeps on the GPU once built, its point sets'
/// bottom levels at the bytes a patch of one sample tile of its largest set, built and
/// compacted: the plan counts them uncompacted, which NVIDIA's driver shrinks to about two
/// thirds, and the compacted size is known only once built. `None` for a scene without
/// patches.
pub(crate) fn compacted_need(
    context: &Arc<GpuContext>,
    scene: &Scene,
    layout: SceneLayout,
    need: &MemoryNeed,
) -> Result<Option<u64>, VulkanError> {
    let largest = scene
        .objects
        .iter()
        .filter_map(|object| match &object.geometry {
            Geometry::Patches(patches) => Some(patches),
            Geometry::Mesh(_) => None,
        })
        .max_by_key(|patches| patches.len());
    let Some(largest) = largest.filter(|patches| !patches.is_empty()) else { return Ok(None) };
    let sample = 0..largest.len().min(SAMPLE_TILE_PATCHES);
    let per_patch =
        tile_blas(context, largest, sample.clone(), layout.blas)?.size() as f64 / sample.len() as f64;
    let patch_structures = (need.patches as f64 * per_patch) as u64;
    Ok(Some(need.held() - need.patch_structures + patch_structures))
}

/// Vertices as vec4 and u32 indices, as the trace reads them.
pub(crate) fn mesh_bytes(mesh: &TriangleMesh) -> u64 {
    mesh.positions.len() as u64 * 16 + mesh.triangles.len() as u64 * 12
}

/// The GPU memory a scene may take: the caller's budget, else the device's largest
/// device-local heap.
pub(crate) struct GpuBudget {
    pub(crate) bytes: u64,
    source: String,
}

impl GpuBudget {
    pub(crate) fn new(context: &GpuContext, budget: Option<u64>) -> Self {
        match budget.filter(|&bytes| bytes > 0) {
            Some(bytes) => Self { bytes, source: "the GPU memory budget".to_string() },
            None => Self {
                bytes: context.info.device_local_bytes,
                source: format!("the device-local memory of {}", context.info.name),
            },
        }
    }

    /// Refuses a scene that cannot fit even with its structures compacted to nothing.
    pub(crate) fn check_plan(&self, need: &MemoryNeed) -> Result<(), VulkanError> {
        if need.floor() <= self.bytes || self.bytes == 0 {
            return Ok(());
        }
        Err(VulkanError::OverBudget(format!(
            "the scene needs at least {:.1} MiB of GPU memory ({:.1} MiB of patch records, meshes and \
             object records; {:.1} MiB for its largest build; at most {:.1} MiB with its {} acceleration \
             structures), over {} of {:.1} MiB; render fewer points or use the CPU backend",
            mib(need.floor()),
            mib(need.buffers),
            mib(need.largest_build),
            mib(need.bound),
            need.bottom_levels + 1,
            self.source,
            mib(self.bytes)
        )))
    }
}

/// What a scene holds on the GPU so far, against its budget.
pub(crate) struct GpuLedger {
    budget: GpuBudget,
    held: u64,
    peak: u64,
}

impl GpuLedger {
    pub(crate) fn new(budget: GpuBudget) -> Self {
        Self { budget, held: 0, peak: 0 }
    }

    /// Ok when `extra` bytes more fit beside what is held; `what` names the step.
    pub(crate) fn check(&self, extra: u64, what: &str) -> Result<(), VulkanError> {
        let need = self.held + extra;
        if need <= self.budget.bytes || self.budget.bytes == 0 {
            return Ok(());
        }
        Err(VulkanError::OverBudget(format!(
            "{what} needs {:.1} MiB of GPU memory beside the {:.1} MiB the scene holds so far, over {} of \
             {:.1} MiB; render fewer points or use the CPU backend",
            mib(extra),
            mib(self.held),
            self.budget.source,
            mib(self.budget.bytes)
        )))
    }

    /// Counts `bytes` as held, and `transient` bytes more as having been held beside them for a
    /// while (a build's input and scratch).
    pub(crate) fn hold(&mut self, bytes: u64, transient: u64) {
        self.peak = self.peak.max(self.held + bytes + transient);
        self.held += bytes;
    }

    /// Counts a built structure as held, and its build, from an `input` of that many bytes, as
    /// having been held beside what was held before it.
    pub(crate) fn hold_structure(&mut self, structure: &AccelerationStructure, input: u64) {
        let size = structure.size();
        self.hold(size, (input + structure.build_bytes).saturating_sub(size));
    }

    /// What is held so far.
    pub(crate) fn held(&self) -> u64 {
        self.held
    }

    /// What the budget leaves beside what is held.
    pub(crate) fn room(&self) -> u64 {
        self.budget.bytes.saturating_sub(self.held)
    }

    /// The most the scene held at once, as far as the ledger saw.
    pub(crate) fn peak(&self) -> u64 {
        self.peak
    }
}

pub(crate) fn mib(bytes: u64) -> f64 {
    bytes as f64 / (1 << 20) as f64
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use ash::vk;
    use bytemuck::Zeroable;
    use glam::{Affine3A, Vec3};
    use pointray_kernels::{Aabb, PatchCold, PatchHot};
    use pointray_patches::PatchSet;
    use pointray_scene::{Background, Camera, Material, SceneObject};

    use super::*;

    const PATCHES: usize = 40_000;

    /// A set of `PATCHES` patches alone: their records are 32 bytes each.
    fn cloud() -> Scene {
        let set = PatchSet {
            aabbs: vec![Aabb::zeroed(); PATCHES].into(),
            hot: vec![PatchHot::zeroed(); PATCHES].into(),
            cold: vec![PatchCold::zeroed(); PATCHES].into(),
            ..PatchSet::default()
        };
        let object = SceneObject {
            name: "cloud".into(),
            transform: Affine3A::IDENTITY,
            material: Material::default(),
            geometry: Geometry::Patches(Arc::new(set)),
        };
        let camera =
            Camera { position: Vec3::Z, look_at: Vec3::ZERO, up: Vec3::Y, vertical_fov_degrees: 45.0 };
        Scene {
            camera,
            lights: Vec::new(),
            background: Background::Gradient { top: Vec3::ONE, bottom: Vec3::ONE },
            objects: vec![object],
        }
    }

    /// Sizes of the kind NVIDIA's driver reports: 32 bytes a box for the structure before
    /// compaction and 32 for the scratch; the top level is negligible here.
    fn sizes(input: &BuildInput<'_>) -> (u64, u64) {
        let primitives: u64 = input.ranges.iter().map(|range| range.primitive_count as u64).sum();
        match input.ty {
            vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL => (32 * primitives, 32 * primitives),
            _ => (64, 64),
        }
    }

    fn plan_for(tile: u32) -> MemoryNeed {
        plan_with_sizes(&cloud(), SceneLayout::default(), tile, sizes)
    }

    #[test]
    fn the_bound_counts_each_build_beside_the_structures_before_it_not_the_records_after() {
        let patches = PATCHES as u64;
        let whole = plan_for(u32::MAX);
        // Boxes, structure, and its scratch or compacted copy: 24 + 32 + 32 bytes a patch,
        // with nothing uploaded before it.
        assert_eq!(whole.largest_build, 88 * patches);
        assert_eq!(whole.bound, 88 * patches, "{whole:?}");
        // In halves, the second half's build (44 bytes a patch) sits beside the first half's
        // structure (16): less than the records and structures at the end (32 + 32), which
        // the top level and the object records add a few hundred bytes to.
        let halves = plan_for(PATCHES as u32 / 2);
        assert_eq!(halves.bottom_levels, 2);
        assert!(halves.bound >= 64 * patches && halves.bound < 64 * patches + 1024, "{halves:?}");
    }

    #[test]
    fn tiles_are_halved_until_the_bound_fits_or_a_build_is_no_larger_than_the_records() {
        let max = u32::MAX;
        assert_eq!(fit_tile(max, 1 << 40, plan_for).0, max, "room for everything: no split");
        let whole = plan_for(max).bound;
        let (tile, need) = fit_tile(max, whole - 1, plan_for);
        assert!(tile < PATCHES as u32 && need.bound < whole, "{tile}: {need:?}");
        // A budget below every bound: halving stops once a tile's build is within the records.
        let (tile, need) = fit_tile(max, 1, plan_for);
        assert!(need.largest_build <= need.buffers, "{tile}: {need:?}");
        assert!(plan_for(tile.saturating_mul(2)).largest_build > need.buffers, "no further than needed");
    }
}
