//! A scene uploaded to the GPU: per-object buffers, per-object (or per-tile) BLASes, the
//! TLAS, the instance (material) records and the lights. Built once, traced many times.

use std::ops::Range;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;
use glam::{Affine3A, Vec3, Vec4};
use pointray_io::TriangleMesh;
use pointray_patches::coarse_level::CoarseLevel;
use pointray_patches::geometry_range::{box_in_range, first_vertex_out_of_range};
use pointray_scene::{Background, BufferLayout, Camera, Geometry, Light, RenderSettings, Scene};
use rayon::prelude::*;

use crate::acceleration::{
    AccelerationStructure, BlasLayout, build, build_peak, build_sizes, instance_input, triangle_input,
};
use crate::buffer::{Buffer, build_input_usage, storage_usage};
use crate::context::GpuContext;
use crate::error::{VkContext, VulkanError};
use crate::gpu_records::{FrameUniforms, LightRecord, ObjectRecord, vec4};
use crate::light_table::LightTable;
use crate::memory_plan::{self, GpuBudget, GpuLedger, INSTANCE_BYTES, mib};
use crate::patch_upload::prepare_patches;
use crate::pipeline::{HIT_GROUP_TRIANGLES, patch_hit_group};
use crate::tile_stream::{MIN_STREAMED_TILE, TileResidency, TileStream};
use pointray_scene::HotRecords;

/// The most instances (meshes and point-set tiles) whose records an instance's 24-bit
/// custom index can name.
const MAX_INSTANCES: usize = (1 << 24) - 1;

pub struct PreparedScene {
    pub(crate) context: Arc<GpuContext>,
    /// The camera `trace` renders from; change it to re-trace from elsewhere.
    pub camera: Camera,
    pub(crate) background: Background,
    /// The background's map, where it is one.
    pub(crate) environment: Option<LightTable>,
    /// The emissive mesh triangles, where there are any, and their count and total area.
    pub(crate) emissive: Option<LightTable>,
    pub(crate) emissive_count: u32,
    pub(crate) emissive_area: f32,
    pub(crate) light_count: u32,
    pub(crate) ray_epsilon: f32,
    pub(crate) objects: Buffer,
    pub(crate) lights: Buffer,
    pub(crate) tlas: AccelerationStructure,
    /// Which per-patch buffers were uploaded; a trace must read those.
    pub(crate) buffer_layout: BufferLayout,
    /// The point sets' bottom levels' layout, chosen or grouped to fit.
    pub(crate) blas_layout: BlasLayout,
    /// The form of the point sets' hot records, chosen to fit.
    pub(crate) hot_records: HotRecords,
    /// The most GPU memory the scene's buffers and structures took at once while it was built.
    pub(crate) build_peak: u64,
    // Kept alive for the TLAS and the shaders' buffer addresses (and measured by
    // `memory_report.rs`).
    pub(crate) _bottom_levels: Vec<AccelerationStructure>,
    pub(crate) _geometry: Vec<Buffer>,
    /// Where the point sets stream: their tiles, and the instances that stay whatever the
    /// camera.
    pub(crate) streaming: Option<Streaming>,
}

/// A streamed scene's tiles (`tile_stream`) and the instances it holds whole (meshes), which
/// come first in every top level it builds.
pub(crate) struct Streaming {
    pub(crate) tiles: TileStream,
    fixed: Vec<(vk::AccelerationStructureInstanceKHR, ObjectRecord)>,
    /// What the scene holds beside the tiles at most: its meshes and a top level over
    /// every tile.
    pub(crate) beside_tiles: u64,
    /// Whether the top level names the resident tiles alone (not while it is rebuilt).
    top_level_current: bool,
    /// Tiles loaded and evicted while the scene was prepared, which the first
    /// `PreparedScene::stream_tiles` reports.
    unreported: (usize, usize),
}

impl Streaming {
    /// The top level over the fixed instances and the resident tiles, and its object records.
    fn top_level(&self, context: &Arc<GpuContext>) -> Result<(AccelerationStructure, Buffer), VulkanError> {
        let (mut instances, mut records): (Vec<_>, Vec<_>) = self.fixed.iter().copied().unzip();
        for tile in self.tiles.resident.values() {
            let hit_group = patch_hit_group(tile.record.patches_per_box, self.tiles.hot_records());
            instances.push(instance(&tile.transform, records.len() as u32, &tile.blas, hit_group));
            records.push(tile.record);
        }
        top_level(context, &instances, &records)
    }
}

/// How a scene goes onto the GPU: its BLAS layout, which per-patch buffers the traces of it
/// will read (only those are uploaded), how large a point set's tiles may be and how much
/// GPU memory it may take.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneLayout {
    pub blas: BlasLayout,
    pub buffers: BufferLayout,
    /// At most this many patches in one BLAS (`pointray_patches::patch_tiles`); the device's
    /// `maxPrimitiveCount` caps it whatever is asked, and so does 2^24 - 1 for sets of more
    /// than 2^27 patches (`patch_upload::patch_tiles`). `None` asks for no other limit.
    pub max_tile_patches: Option<u32>,
    /// Bytes of GPU memory the scene may take, building included; `None` is the device's
    /// `DeviceOptions::gpu_memory`, else its device-local memory. A scene that cannot fit is
    /// refused before anything is uploaded, one that may not before the step that would not.
    pub memory_budget: Option<u64>,
    /// `Some(image size)`: where the scene's point sets do not fit the budget, stream them
    /// rather than refuse the scene. Their tiles are loaded as far as the budget allows, in
    /// the order a camera rendering an image of this size needs them, first for the scene's
    /// camera and then for each `PreparedScene::stream_tiles`.
    pub stream_tiles_for: Option<(u32, u32)>,
    /// Where tiles stream, draw those the budget cannot hold in full from their coarse level
    /// (`tile_stream`) rather than leave them out. `render`, `view` and `bench` do.
    pub coarse_tiles: bool,
    /// Where the scene does not fit the budget whole with `blas`, try it in boxes of
    /// `PATCHES_PER_BOX_TO_FIT` patches before streaming or refusing it.
    pub group_to_fit: bool,
    /// The form of the point sets' hot records on the GPU. Unpacked records need boxes of
    /// one patch and split buffers.
    pub hot_records: HotRecords,
    /// Where the scene's point sets hold at most `UNPACKED_MOST_PATCHES` patches and the
    /// scene, in boxes of one patch and split buffers, fits the budget whole with unpacked hot
    /// records, take them.
    pub unpack_to_fit: bool,
}

/// The most patches a scene's point sets may hold to take unpacked hot records when the
/// choice is left open. Measured on an H200 (bench/RESULTS.md, "Unpacked hot records"):
/// unpacked records trace Table 1's models 2-8% faster, and the scale ladder's 1M to 100M
/// rungs 4-6% faster, sparing every intersection call the decoding; but the 300M rung, the
/// first cut into bottom levels of 16M patches, 4% slower at 1920x1080 and 18% at 640x640.
pub const UNPACKED_MOST_PATCHES: usize = 100_000_000;

/// The patches a box where one a box does not fit (`SceneLayout::group_to_fit`). Measured
/// on an H200 (bench/RESULTS.md, "Boxes of several patches"): boxes of 4 take 37 GPU bytes a
/// point against 52 with one, and trace Table 1's models 1.5-1.6 times slower; boxes of 2
/// save too little (a BLAS of about 10 bytes a point) and of 8 cost twice the time.
pub const PATCHES_PER_BOX_TO_FIT: u32 = 4;

impl SceneLayout {
    /// The layout whose buffers a trace with `settings` reads, with one BLAS geometry of
    /// `settings`' patches a box, or where it leaves them open one, grouped to fit.
    pub fn for_settings(settings: &RenderSettings) -> Self {
        Self {
            buffers: settings.buffer_layout,
            blas: BlasLayout::grouping(settings.patches_per_box.unwrap_or(1)),
            group_to_fit: settings.patches_per_box.is_none()
                && settings.hot_records != Some(HotRecords::Unpacked),
            hot_records: settings.hot_records.unwrap_or_default(),
            unpack_to_fit: settings.hot_records.is_none(),
            ..Self::default()
        }
    }

    /// The layout of `for_settings` for frames of `settings`' size, as `render`, `view` and
    /// `bench` make them: point sets that do not fit the budget whole stream their tiles,
    /// drawing coarse those it cannot hold.
    pub fn for_frames(settings: &RenderSettings) -> Self {
        Self {
            stream_tiles_for: Some((settings.width, settings.height)),
            coarse_tiles: true,
            ..Self::for_settings(settings)
        }
    }

    /// Whether unpacked records can be read in this layout: by the hit group of boxes of one
    /// patch, from split buffers.
    fn reads_unpacked(&self) -> bool {
        self.buffers == BufferLayout::Split && self.blas.patches_per_box() == 1
    }

    /// Whether to try `scene` with unpacked hot records: the layout leaves them open
    /// (`unpack_to_fit`), can read them, and the point sets are small enough to gain by them.
    fn unpacks(&self, scene: &Scene) -> bool {
        self.unpack_to_fit
            && self.reads_unpacked()
            && (1..=UNPACKED_MOST_PATCHES).contains(&point_set_patches(scene))
    }

    fn check_hot_records(&self) -> Result<(), VulkanError> {
        if self.hot_records == HotRecords::Unpacked && !self.reads_unpacked() {
            return Err(VulkanError::InvalidSettings(
                "unpacked hot records need boxes of one patch (patches_per_box = 1) and split buffers".into(),
            ));
        }
        Ok(())
    }

    /// This layout in boxes of `PATCHES_PER_BOX_TO_FIT` patches, not to be grouped again.
    fn grouped_to_fit(self) -> Self {
        Self {
            blas: BlasLayout::PatchGroups(PATCHES_PER_BOX_TO_FIT),
            group_to_fit: false,
            hot_records: HotRecords::Packed,
            unpack_to_fit: false,
            ..self
        }
    }

    /// The most patches one tile holds on `context`'s device.
    fn tile_limit(&self, context: &GpuContext) -> u32 {
        let device = u32::try_from(context.info.max_blas_primitives).unwrap_or(u32::MAX).max(1);
        self.max_tile_patches.unwrap_or(u32::MAX).clamp(1, device)
    }
}

/// One object's contribution: its record (addresses only), its bottom levels (none when
/// it is empty, one per tile of a point set) with the patches of each (none for a mesh),
/// and the buffers its traces read.
pub(crate) struct PreparedObject {
    pub(crate) record: ObjectRecord,
    pub(crate) bottom_levels: Vec<(AccelerationStructure, Range<usize>)>,
    pub(crate) buffers: Vec<Buffer>,
}

fn prepare_mesh(
    context: &Arc<GpuContext>,
    mesh: &TriangleMesh,
    ledger: &mut GpuLedger,
) -> Result<PreparedObject, VulkanError> {
    let vertex_count = mesh.positions.len();
    if let Some(bad) = mesh.triangles.iter().flatten().find(|&&i| i as usize >= vertex_count) {
        return Err(VulkanError::InvalidScene(format!(
            "a mesh triangle uses vertex {bad}, but the mesh has {vertex_count}"
        )));
    }
    let triangle_count = mesh.triangles.len() as u32;
    let input = |vertices: vk::DeviceAddress, indices: vk::DeviceAddress| {
        triangle_input(vertices, vertex_count as u32, indices, triangle_count)
    };
    // Checked before each step, so that a mesh over the budget is refused, not built past it.
    let buffer_bytes = memory_plan::mesh_bytes(mesh);
    ledger.check(buffer_bytes, "a mesh's vertices and indices")?;
    if triangle_count > 0 {
        let (structure, scratch) = build_sizes(context, &input(0, 0));
        ledger.check(buffer_bytes + build_peak(0, structure, scratch), "a mesh's bottom-level build")?;
    }
    let vertices: Vec<Vec4> = mesh.positions.iter().map(|p| p.extend(1.0)).collect();
    let vertices = Buffer::device_with_data(
        context,
        "mesh vertices",
        bytemuck::cast_slice(&vertices),
        build_input_usage(),
    )?;
    let indices = Buffer::device_with_data(
        context,
        "mesh indices",
        bytemuck::cast_slice(&mesh.triangles),
        build_input_usage(),
    )?;
    ledger.hold(vertices.size + indices.size, 0);
    let blas = (triangle_count > 0)
        .then(|| build(context, &input(vertices.device_address(), indices.device_address())))
        .transpose()?;
    if let Some(blas) = &blas {
        ledger.hold_structure(blas, 0);
    }
    let record = ObjectRecord {
        vertices: vertices.device_address(),
        indices: indices.device_address(),
        ..ObjectRecord::default()
    };
    let bottom_levels = blas.into_iter().map(|blas| (blas, 0..0)).collect();
    Ok(PreparedObject { record, bottom_levels, buffers: vec![vertices, indices] })
}

/// Object to world as the 3x4 row-major matrix Vulkan instances carry.
fn instance_transform(transform: &Affine3A) -> vk::TransformMatrixKHR {
    let m = transform.matrix3;
    let t = transform.translation;
    let row = |r: usize| [m.x_axis[r], m.y_axis[r], m.z_axis[r], t[r]];
    let [a, b, c] = [row(0), row(1), row(2)];
    vk::TransformMatrixKHR {
        matrix: [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3], c[0], c[1], c[2], c[3]],
    }
}

fn instance(
    transform: &Affine3A,
    record_index: u32,
    blas: &AccelerationStructure,
    hit_group: u32,
) -> vk::AccelerationStructureInstanceKHR {
    vk::AccelerationStructureInstanceKHR {
        transform: instance_transform(transform),
        instance_custom_index_and_mask: vk::Packed24_8::new(record_index, 0xff),
        instance_shader_binding_table_record_offset_and_flags: vk::Packed24_8::new(
            hit_group,
            // Point-set patches and meshes are seen from both sides.
            vk::GeometryInstanceFlagsKHR::TRIANGLE_FACING_CULL_DISABLE.as_raw() as u8,
        ),
        acceleration_structure_reference: vk::AccelerationStructureReferenceKHR {
            device_handle: blas.address,
        },
    }
}

fn instance_bytes(instances: &[vk::AccelerationStructureInstanceKHR]) -> &[u8] {
    // SAFETY: the instance record is a plain repr(C) struct of 64 bytes with no padding.
    unsafe { std::slice::from_raw_parts(instances.as_ptr().cast::<u8>(), std::mem::size_of_val(instances)) }
}

/// The light records in host-visible memory, so that moving a light is a write, not a
/// re-preparation.
fn light_buffer(context: &Arc<GpuContext>, lights: &[Light]) -> Result<Buffer, VulkanError> {
    let records: Vec<LightRecord> = lights.iter().map(LightRecord::from).collect();
    // Storage buffers may not be empty: an empty list still gets one (unread) record.
    let bytes = if records.is_empty() { vec![0u8; 32] } else { bytemuck::cast_slice(&records).to_vec() };
    Buffer::host_with_data(context, "light records", &bytes, vk::BufferUsageFlags::STORAGE_BUFFER)
}

impl PreparedScene {
    /// Which per-patch buffers this scene holds on the GPU.
    pub fn buffer_layout(&self) -> BufferLayout {
        self.buffer_layout
    }

    /// A trace must read the per-patch buffers that were uploaded; any other address is 0.
    pub(crate) fn check_buffers_for(&self, settings: &RenderSettings) -> Result<(), VulkanError> {
        if settings.buffer_layout == self.buffer_layout {
            return Ok(());
        }
        let name = |layout| match layout {
            BufferLayout::Split => "split hot and cold",
            BufferLayout::Combined => "combined",
        };
        Err(VulkanError::InvalidSettings(format!(
            "the trace reads the {} patch buffers, but the scene was prepared with the {} ones only; \
             prepare it with the trace's layout (SceneLayout::for_settings)",
            name(settings.buffer_layout),
            name(self.buffer_layout)
        )))
    }

    /// Where the scene's point sets stream (`SceneLayout::stream_tiles_for`): evicts the
    /// tiles the scene's camera, rendering an image `aspect` (width over height) wide, no
    /// longer needs, loads the ones it needs, most needed first, for at most `limit` (at
    /// least one tile a call), and rebuilds the top level if anything changed. `None` for a
    /// scene held whole.
    pub fn stream_tiles(
        &mut self,
        aspect: f32,
        limit: Option<Duration>,
    ) -> Result<Option<TileResidency>, VulkanError> {
        let Some(streaming) = &mut self.streaming else { return Ok(None) };
        let context = &self.context;
        let idle = || {
            // SAFETY: the device is alive; waiting for it to go idle has no other requirement.
            unsafe { context.device.device_wait_idle() }.during("waiting to stream tiles")
        };
        // Frames in flight may read the tiles evicted and the top level replaced; a load that
        // fails may follow evictions, so the top level is rebuilt over what is resident then.
        let updated = streaming.tiles.update(context, &self.camera, aspect, limit, idle);
        if streaming.tiles.take_changes() || !streaming.top_level_current {
            streaming.top_level_current = false;
            (self.tlas, self.objects) = streaming.top_level(context)?;
            streaming.top_level_current = true;
        }
        let residency = updated?;
        let (loaded, evicted) = std::mem::take(&mut streaming.unreported);
        Ok(Some(TileResidency {
            loaded: residency.loaded + loaded,
            evicted: residency.evicted + evicted,
            ..residency
        }))
    }

    /// Refuses to trace a streamed scene whose top level may name evicted tiles.
    pub(crate) fn check_traceable(&self) -> Result<(), VulkanError> {
        match &self.streaming {
            Some(streaming) if !streaming.top_level_current => Err(VulkanError::InvalidScene(
                "the streamed scene's top level could not be rebuilt after its tiles changed; stream its \
                 tiles again"
                    .into(),
            )),
            _ => Ok(()),
        }
    }

    /// Replaces the scene's lights; the next trace shades with them. Geometry, and so every
    /// acceleration structure, stays as it is.
    pub fn set_lights(&mut self, lights: &[Light]) -> Result<(), VulkanError> {
        let bytes = lights.len() * std::mem::size_of::<LightRecord>();
        if lights.is_empty() || bytes as u64 > self.lights.size {
            self.lights = light_buffer(&self.context, lights)?;
        } else {
            let records: Vec<LightRecord> = lights.iter().map(LightRecord::from).collect();
            self.lights.write(bytemuck::cast_slice(&records));
        }
        self.light_count = lights.len() as u32;
        Ok(())
    }
}

/// Why an object cannot go into an acceleration structure, if it cannot: the device's build
/// is undefined for NaN or infinite boxes.
fn out_of_range(object: &pointray_scene::SceneObject) -> Option<String> {
    let problem = match &object.geometry {
        _ if !object.transform.is_finite() => "its transform is not finite".to_string(),
        Geometry::Patches(patches) => {
            let bad = patches.aabbs.par_iter().position_first(|aabb| !box_in_range(aabb))?;
            format!("patch box {bad} is not finite or out of range")
        }
        Geometry::Mesh(mesh) => {
            format!("vertex {} is not finite or out of range", first_vertex_out_of_range(mesh)?)
        }
    };
    Some(format!("object {:?}: {problem}", object.name))
}

/// Uploads `scene` and builds its acceleration structures.
pub(crate) fn prepare(
    context: &Arc<GpuContext>,
    scene: &Scene,
    layout: SceneLayout,
) -> Result<PreparedScene, VulkanError> {
    if let Some(problem) = scene.objects.iter().find_map(out_of_range) {
        return Err(VulkanError::InvalidScene(problem));
    }
    layout.check_hot_records()?;
    if layout.unpacks(scene) {
        return prepare_unpacked_to_fit(context, scene, SceneLayout { unpack_to_fit: false, ..layout });
    }
    let streams = layout.stream_tiles_for.is_some() && has_point_sets(scene);
    if (layout.group_to_fit || streams) && !fits_compacted(context, scene, layout)? {
        if layout.group_to_fit {
            tracing::info!(
                "boxes of {PATCHES_PER_BOX_TO_FIT} patches, as the scene would not fit whole in boxes of one"
            );
            return prepare(context, scene, layout.grouped_to_fit());
        }
        tracing::info!("streaming the point sets' tiles, as the scene would not fit whole");
        return upload(context, scene, layout, true);
    }
    // The estimates before the upload can err: the ledger has the last word.
    match upload(context, scene, layout, false) {
        Err(VulkanError::OverBudget(why)) if layout.group_to_fit && has_point_sets(scene) => {
            tracing::info!(
                "boxes of {PATCHES_PER_BOX_TO_FIT} patches, as the scene does not fit whole in boxes of one: {why}"
            );
            prepare(context, scene, layout.grouped_to_fit())
        }
        Err(VulkanError::OverBudget(why)) if streams => {
            tracing::info!("streaming the point sets' tiles, as the scene does not fit whole: {why}");
            upload(context, scene, layout, true)
        }
        result => result,
    }
}

/// `scene` whole in `packed` with unpacked hot records, where it fits so, else prepared in
/// `packed`. Streaming, grouping and the coarse level all keep records packed: a scene that
/// does not fit whole needs the memory more than the speed.
fn prepare_unpacked_to_fit(
    context: &Arc<GpuContext>,
    scene: &Scene,
    packed: SceneLayout,
) -> Result<PreparedScene, VulkanError> {
    let unpacked = SceneLayout { hot_records: HotRecords::Unpacked, ..packed };
    if !fits_compacted(context, scene, unpacked)? {
        return prepare(context, scene, packed);
    }
    match upload(context, scene, unpacked, false) {
        Err(VulkanError::OverBudget(why)) => {
            tracing::info!("packed hot records, as the scene does not fit whole with unpacked ones: {why}");
            prepare(context, scene, packed)
        }
        result => result,
    }
}

/// Uploads `scene` whole, or with `streamed` its meshes alone and its point sets' tiles as
/// the camera needs them.
fn upload(
    context: &Arc<GpuContext>,
    scene: &Scene,
    layout: SceneLayout,
    streamed: bool,
) -> Result<PreparedScene, VulkanError> {
    let budget = GpuBudget::new(context, layout.memory_budget.or(context.gpu_memory));
    // A streamed scene's point sets are not uploaded here, so their tiles need no plan.
    let max_tile = (!streamed).then(|| planned_tile(context, scene, layout, &budget)).transpose()?;
    let mut ledger = GpuLedger::new(budget);
    let (mut records, mut instances, mut bottom_levels, mut geometry) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (index, object) in scene.objects.iter().enumerate() {
        let (prepared, hit_group) = match (&object.geometry, max_tile) {
            (Geometry::Patches(_), None) => continue,
            (Geometry::Patches(patches), Some(max_tile)) => (
                prepare_patches(context, patches, &object.material, layout, max_tile, &mut ledger)?,
                patch_hit_group(layout.blas.patches_per_box(), layout.hot_records),
            ),
            (Geometry::Mesh(mesh), _) => (prepare_mesh(context, mesh, &mut ledger)?, HIT_GROUP_TRIANGLES),
        };
        let record = prepared.record.with_material(&object.material);
        for (blas, tile) in prepared.bottom_levels {
            instances.push(instance(&object.transform, records.len() as u32, &blas, hit_group));
            records.push(record.for_tile(index as u32, tile, layout.blas));
            bottom_levels.push(blas);
        }
        geometry.extend(prepared.buffers);
    }
    let streaming = streamed
        .then(|| start_streaming(context, scene, layout, &ledger, &instances, &records))
        .transpose()?;
    let (tlas, objects) = top_level(context, &instances, &records)?;
    ledger.hold_structure(&tlas, instance_bytes(&instances).len() as u64);
    let emissive = scene.emissive_triangles();
    let mut prepared = PreparedScene {
        context: context.clone(),
        camera: scene.camera,
        background: scene.background.clone(),
        environment: match &scene.background {
            Background::Map(map) => Some(LightTable::environment(context, map)?),
            _ => None,
        },
        emissive: LightTable::emissive(context, &emissive)?,
        emissive_count: emissive.count(),
        emissive_area: emissive.total_area(),
        light_count: scene.lights.len() as u32,
        ray_epsilon: scene.ray_epsilon(),
        objects,
        lights: light_buffer(context, &scene.lights)?,
        tlas,
        buffer_layout: layout.buffers,
        blas_layout: layout.blas,
        hot_records: layout.hot_records,
        build_peak: ledger.peak(),
        _bottom_levels: bottom_levels,
        _geometry: geometry,
        streaming,
    };
    if let Some((width, height)) = layout.stream_tiles_for.filter(|_| streamed) {
        let first = prepared.stream_tiles(width as f32 / height.max(1) as f32, None)?;
        if let (Some(streaming), Some(first)) = (&mut prepared.streaming, first) {
            streaming.unreported = (first.loaded, first.evicted);
        }
    }
    Ok(prepared)
}

/// Whether `scene` in `layout` fits its budget once built: surely where its structures fit
/// uncompacted, else by the estimate of `memory_plan::compacted_need`.
fn fits_compacted(
    context: &Arc<GpuContext>,
    scene: &Scene,
    layout: SceneLayout,
) -> Result<bool, VulkanError> {
    let budget = GpuBudget::new(context, layout.memory_budget.or(context.gpu_memory));
    let need = memory_plan::plan(context, scene, layout, layout.tile_limit(context));
    if need.held() <= budget.bytes {
        return Ok(true);
    }
    let compacted = memory_plan::compacted_need(context, scene, layout, &need)?;
    Ok(compacted.is_none_or(|bytes| bytes <= budget.bytes))
}

/// The largest tile of the scene's point sets that fits `budget` (`memory_plan`), or why the
/// scene cannot fit.
fn planned_tile(
    context: &GpuContext,
    scene: &Scene,
    layout: SceneLayout,
    budget: &GpuBudget,
) -> Result<u32, VulkanError> {
    let (max_tile, need) =
        memory_plan::fitted_tile(context, scene, layout, layout.tile_limit(context), budget);
    if need.bottom_levels > MAX_INSTANCES {
        return Err(VulkanError::InvalidScene(format!(
            "{} meshes and point-set tiles of at most {max_tile} patches; at most {MAX_INSTANCES} fit",
            need.bottom_levels
        )));
    }
    budget.check_plan(&need)?;
    Ok(max_tile)
}

fn has_point_sets(scene: &Scene) -> bool {
    scene.objects.iter().any(|object| matches!(object.geometry, Geometry::Patches(_)))
}

/// The patches of all of `scene`'s point sets.
fn point_set_patches(scene: &Scene) -> usize {
    let patches = |object: &pointray_scene::SceneObject| match &object.geometry {
        Geometry::Patches(patches) => patches.len(),
        Geometry::Mesh(_) => 0,
    };
    scene.objects.iter().map(patches).sum()
}

/// The tiles of `scene`'s point sets, none loaded, with a budget of what `ledger`'s leaves
/// beside the scene's other holdings (`instances` and `records` so far), a top level over
/// every tile (built beside the one it replaces) and one tile's build.
fn start_streaming(
    context: &Arc<GpuContext>,
    scene: &Scene,
    layout: SceneLayout,
    ledger: &GpuLedger,
    instances: &[vk::AccelerationStructureInstanceKHR],
    records: &[ObjectRecord],
) -> Result<Streaming, VulkanError> {
    let coarse = if layout.coarse_tiles { coarse_levels(scene) } else { Vec::new() };
    let mut max_tile = layout.tile_limit(context);
    loop {
        let (tiles, largest_build) = TileStream::new(context, scene, layout, max_tile, &coarse)?;
        let largest = tiles.largest_tile_patches();
        match stream_within_budget(context, (tiles, largest_build), ledger, instances, records) {
            // Smaller tiles take less room to build and to hold one of.
            Err(VulkanError::OverBudget(_)) if largest / 2 >= MIN_STREAMED_TILE => {
                max_tile = (largest / 2) as u32;
            }
            started => return started,
        }
    }
}

/// The coarse level of each of `scene`'s point sets, in order, for whichever tiles they are
/// cut into: their blocks' (`pointray_patches::coarse_level`), as their stores hold it, or
/// made now for a set made in memory.
fn coarse_levels(scene: &Scene) -> Vec<Arc<CoarseLevel>> {
    let started = Instant::now();
    let levels: Vec<Arc<CoarseLevel>> = (scene.objects.iter())
        .filter_map(|object| match &object.geometry {
            Geometry::Patches(patches) => Some(patches.coarse_level()),
            Geometry::Mesh(_) => None,
        })
        .collect();
    let coarse: usize = levels.iter().map(|level| level.patches.len()).sum();
    tracing::info!("took the point sets' coarse levels ({coarse} patches) in {:.2?}", started.elapsed());
    levels
}

/// `tiles` streamed beside the scene's other holdings, or why the budget cannot hold them.
fn stream_within_budget(
    context: &GpuContext,
    (mut tiles, largest_build): (TileStream, u64),
    ledger: &GpuLedger,
    instances: &[vk::AccelerationStructureInstanceKHR],
    records: &[ObjectRecord],
) -> Result<Streaming, VulkanError> {
    let count = instances.len() + tiles.len();
    if count > MAX_INSTANCES {
        return Err(VulkanError::InvalidScene(format!(
            "{count} meshes and point-set tiles; at most {MAX_INSTANCES} fit"
        )));
    }
    let (tlas, scratch) = build_sizes(context, &instance_input(0, count as u32));
    let object_records = count as u64 * size_of::<ObjectRecord>() as u64;
    // The top level in use and its object records stay until their rebuild replaces them.
    let replaced = tlas + object_records;
    let top = build_peak(count as u64 * INSTANCE_BYTES, tlas, scratch) + object_records + replaced;
    let reserved = top + largest_build;
    ledger.check(
        reserved,
        "streaming the point sets' tiles (a top level over them all, built beside the one it replaces, \
         and one tile's build)",
    )?;
    let room = ledger.room().saturating_sub(reserved);
    if room < tiles.smallest_tile_bytes() {
        return Err(VulkanError::OverBudget(format!(
            "streaming the point sets' tiles leaves {:.1} MiB for them beside a top level over them all, \
             the one it replaces and one tile's build ({:.1} MiB), less than their smallest tile takes \
             ({:.1} MiB); raise the GPU memory budget or use the CPU backend",
            mib(room),
            mib(reserved),
            mib(tiles.smallest_tile_bytes())
        )));
    }
    tiles.set_budget(room);
    let fixed = instances.iter().copied().zip(records.iter().copied()).collect();
    Ok(Streaming {
        tiles,
        fixed,
        beside_tiles: ledger.held() + top,
        top_level_current: true,
        unreported: (0, 0),
    })
}

/// The top level over `instances` and the object records the shaders index by their
/// custom indices.
fn top_level(
    context: &Arc<GpuContext>,
    instances: &[vk::AccelerationStructureInstanceKHR],
    records: &[ObjectRecord],
) -> Result<(AccelerationStructure, Buffer), VulkanError> {
    // Like the boxes, the instances are only the build's input.
    let instance_buffer =
        Buffer::device_with_data(context, "TLAS instances", instance_bytes(instances), build_input_usage())?;
    let tlas = build(context, &instance_input(instance_buffer.device_address(), instances.len() as u32))?;
    drop(instance_buffer);
    // Storage buffers may not be empty.
    let record_bytes = if records.is_empty() {
        vec![0u8; size_of::<ObjectRecord>()]
    } else {
        bytemuck::cast_slice(records).to_vec()
    };
    let objects = Buffer::device_with_data(context, "object records", &record_bytes, storage_usage())?;
    Ok((tlas, objects))
}

impl PreparedScene {
    /// The uniforms (`FrameUniforms`) a trace of this scene reads: its camera, its background
    /// (with the addresses of its map's table, where it is a map) and its emissive triangles'
    /// table.
    pub(crate) fn frame_uniforms(&self) -> FrameUniforms {
        let (camera, background) = (&self.camera, &self.background);
        // A solid background is the gradient between two equal colours.
        let (top, bottom) = match background {
            Background::Solid(color) => (*color, *color),
            Background::Gradient { top, bottom } => (*top, *bottom),
            Background::Map(_) => (Vec3::ZERO, Vec3::ZERO),
        };
        let (width, height, rotation) = match background {
            Background::Map(map) => (map.width(), map.height(), map.rotation()),
            _ => (0, 0, 0.0),
        };
        let records = |table: &Option<LightTable>| table.as_ref().map_or(0, |t| t.records.device_address());
        let distribution =
            |table: &Option<LightTable>| table.as_ref().map_or(0, |t| t.distribution.device_address());
        FrameUniforms {
            camera_position_fov: vec4(camera.position, camera.vertical_fov_degrees),
            camera_look_at: vec4(camera.look_at, 0.0),
            camera_up: vec4(camera.up, 0.0),
            background_top: vec4(top, 0.0),
            background_bottom: vec4(bottom, 0.0),
            light_count: self.light_count,
            ray_epsilon: self.ray_epsilon,
            sky_lit: background.is_lit().into(),
            sky_is_map: self.environment.is_some().into(),
            sky_texels: records(&self.environment),
            sky_distribution: distribution(&self.environment),
            sky_width: width,
            sky_height: height,
            sky_rotation: rotation,
            emissive_count: self.emissive_count,
            emissive_records: records(&self.emissive),
            emissive_distribution: distribution(&self.emissive),
            emissive_total_area: self.emissive_area,
            pad: [0; 3],
        }
    }
}
