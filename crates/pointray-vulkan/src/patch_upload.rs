//! A point set onto the GPU: one BLAS per tile (`pointray_surface::patch_tiles`), then the
//! per-patch records its traces read, all tiles sharing the set's buffers.

use std::ops::Range;
use std::sync::Arc;
use std::time::{Duration, Instant};

use pointray_kernels::{COLOR_NEIGHBORS, NO_NEIGHBOR};
use pointray_scene::{BufferLayout, Material};
use pointray_surface::PatchSet;
use pointray_surface::patch_tiles::tile_ranges;

use crate::acceleration::{AccelerationStructure, aabb_input, build, build_peak, build_sizes};
use crate::buffer::{Buffer, build_input_usage, storage_usage};
use crate::context::GpuContext;
use crate::error::VulkanError;
use crate::gpu_records::{ObjectRecord, PatchCombined};
use crate::memory_plan::GpuLedger;
use crate::prepared_scene::{PreparedObject, SceneLayout};

/// Bytes of one patch box (`VkAabbPositionsKHR`).
const BOX_BYTES: u64 = size_of::<pointray_kernels::Aabb>() as u64;

/// Whether a trace of a point set with `material` reads its cold records and colour
/// neighbours: only to colour hits by the points, so for the others they stay in memory.
pub(crate) fn reads_point_colors(material: &Material) -> bool {
    material.use_point_colors
}

/// The tiles of `patches` for a device whose BLASes hold at most `max_tile_patches`.
pub(crate) fn patch_tiles(patches: &PatchSet, max_tile_patches: u32) -> Vec<Range<usize>> {
    tile_ranges(patches.len(), max_tile_patches as usize)
}

pub(crate) fn prepare_patches(
    context: &Arc<GpuContext>,
    patches: &PatchSet,
    material: &Material,
    layout: SceneLayout,
    max_tile_patches: u32,
    ledger: &mut GpuLedger,
) -> Result<PreparedObject, VulkanError> {
    let count = patches.len();
    if patches.aabbs.len() != count || patches.cold.len() != count {
        return Err(VulkanError::InvalidScene(format!(
            "a patch set has {} hot records, {} cold records and {} boxes; they must match",
            count,
            patches.cold.len(),
            patches.aabbs.len()
        )));
    }
    check_color_neighbors(patches)?;
    let colors = reads_point_colors(material);
    let records = record_bytes(patches, material, layout.buffers);
    let started = Instant::now();
    let bottom_levels = tile_bottom_levels(context, patches, layout, max_tile_patches, records, ledger)?;
    let what = format!("built {} bottom levels over {count} patches (boxes uploaded)", bottom_levels.len());
    log_phase(&what, count as u64 * BOX_BYTES, started.elapsed());
    ledger.check(records, "uploading the patch records")?;
    let started = Instant::now();
    let (mut record, mut buffers) = patch_records(context, patches, layout.buffers, colors)?;
    // Only coloured clouds carry neighbour lists; the others keep address 0, which the
    // closest-hit shader never dereferences.
    if colors && !patches.color_neighbors.is_empty() {
        let lists = Buffer::device_with_data(
            context,
            "colour neighbour lists",
            bytemuck::cast_slice(&patches.color_neighbors),
            storage_usage(),
        )?;
        record.color_neighbors = lists.device_address();
        buffers.push(lists);
    }
    let uploaded: u64 = buffers.iter().map(|buffer| buffer.size).sum();
    ledger.hold(uploaded, 0);
    log_phase(&format!("uploaded {count} patches' records"), uploaded, started.elapsed());
    Ok(PreparedObject { record, bottom_levels, buffers })
}

/// One line per phase of a point set's way onto the GPU, which for a large set takes
/// seconds: what was done, the bytes moved and the rate.
fn log_phase(what: &str, bytes: u64, elapsed: Duration) {
    let (gigabytes, seconds) = (bytes as f64 / 1e9, elapsed.as_secs_f64());
    tracing::info!("{what}: {gigabytes:.2} GB in {seconds:.2} s ({:.2} GB/s)", gigabytes / seconds.max(1e-9));
}

/// One BLAS per tile, each with its first patch, built before the set's `records` bytes are
/// uploaded. Each tile's boxes are uploaded for its build alone: the structure keeps its own
/// copy and no shader reads them.
fn tile_bottom_levels(
    context: &Arc<GpuContext>,
    patches: &PatchSet,
    layout: SceneLayout,
    max_tile_patches: u32,
    records: u64,
    ledger: &mut GpuLedger,
) -> Result<Vec<(AccelerationStructure, u32)>, VulkanError> {
    let tiles = patch_tiles(patches, max_tile_patches);
    let count = tiles.len();
    let mut bottom_levels = Vec::with_capacity(count);
    for (index, tile) in tiles.into_iter().enumerate() {
        let primitives = tile.len() as u32;
        let (size, scratch) = build_sizes(context, &aabb_input(0, primitives, layout.blas));
        let transient = build_peak(tile_box_bytes(&tile), size, scratch);
        // The records come after the last build, so a build that leaves no room for them fails now.
        let step =
            format!("building bottom level {} of {count} (and the patch records after the last)", index + 1);
        ledger.check(transient.max(records), &step)?;
        let boxes = Buffer::device_with_data(
            context,
            "patch boxes",
            bytemuck::cast_slice(&patches.aabbs[tile.clone()]),
            build_input_usage(),
        )?;
        let blas = build(context, &aabb_input(boxes.device_address(), primitives, layout.blas))?;
        ledger.hold_structure(&blas, boxes.size);
        bottom_levels.push((blas, tile.start as u32));
    }
    Ok(bottom_levels)
}

/// The per-patch records the trace reads, in `buffers`' layout only: the hot buffer (and
/// the cold one where the trace colours hits by the points), or the combined one. The colour
/// blend walks the split hot and cold buffers (`interpolate_color`), so where the trace
/// colours hits by the points the combined layout uploads them too.
fn patch_records(
    context: &Arc<GpuContext>,
    patches: &PatchSet,
    buffers: BufferLayout,
    colors: bool,
) -> Result<(ObjectRecord, Vec<Buffer>), VulkanError> {
    let upload = |name, bytes: &[u8]| Buffer::device_with_data(context, name, bytes, storage_usage());
    let mut record = ObjectRecord::default();
    let mut uploaded = Vec::new();
    if buffers == BufferLayout::Split || colors {
        let hot = upload("hot patch records", bytemuck::cast_slice(&patches.hot))?;
        record.hot = hot.device_address();
        uploaded.push(hot);
    }
    if colors {
        let cold = upload("cold patch records", bytemuck::cast_slice(&patches.cold))?;
        record.cold = cold.device_address();
        uploaded.push(cold);
    }
    if buffers == BufferLayout::Combined {
        let combined: Vec<PatchCombined> = patches
            .hot
            .iter()
            .zip(&patches.cold)
            .map(|(&hot, &cold)| PatchCombined::new(hot, cold))
            .collect();
        let combined = upload("combined patch records", bytemuck::cast_slice(&combined))?;
        record.combined = combined.device_address();
        uploaded.push(combined);
    }
    Ok((record, uploaded))
}

/// The GPU bytes of the records a trace of `patches` with `material` reads.
pub(crate) fn record_bytes(patches: &PatchSet, material: &Material, buffers: BufferLayout) -> u64 {
    let count = patches.len() as u64;
    let hot = size_of::<pointray_kernels::PatchHot>() as u64;
    let cold = size_of::<pointray_kernels::PatchCold>() as u64;
    let colors = reads_point_colors(material);
    let neighbors = if colors { patches.color_neighbors.len() as u64 * 4 } else { 0 };
    let split = match (buffers, colors) {
        (_, true) => count * (hot + cold),
        (BufferLayout::Split, false) => count * hot,
        (BufferLayout::Combined, false) => 0,
    };
    let combined =
        if buffers == BufferLayout::Combined { count * size_of::<PatchCombined>() as u64 } else { 0 };
    neighbors + split + combined
}

/// The build input of one tile: its patches' boxes.
pub(crate) fn tile_box_bytes(tile: &Range<usize>) -> u64 {
    tile.len() as u64 * BOX_BYTES
}

/// The shader follows neighbour indices without bounds checks: each list must have its
/// `COLOR_NEIGHBORS` slots and name only patches of its set.
fn check_color_neighbors(patches: &PatchSet) -> Result<(), VulkanError> {
    let (count, neighbors) = (patches.len(), &patches.color_neighbors);
    if !neighbors.is_empty() && neighbors.len() != count * COLOR_NEIGHBORS {
        return Err(VulkanError::InvalidScene(format!(
            "a patch set has {} colour neighbour entries for {count} patches; {COLOR_NEIGHBORS} per patch wanted",
            neighbors.len()
        )));
    }
    match neighbors.iter().position(|&j| j != NO_NEIGHBOR && j as usize >= count) {
        Some(bad) => Err(VulkanError::InvalidScene(format!(
            "patch {} names colour neighbour {}, but the set has {count} patches",
            bad / COLOR_NEIGHBORS,
            neighbors[bad]
        ))),
        None => Ok(()),
    }
}
