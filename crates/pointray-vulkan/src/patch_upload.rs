//! A point set onto the GPU: one BLAS per tile (`pointray_patches::patch_tiles`), then the
//! per-patch records its traces read, all tiles sharing the set's buffers.

use std::borrow::Cow;
use std::ops::Range;
use std::sync::Arc;
use std::time::{Duration, Instant};

use pointray_kernels::{Aabb, COLOR_NEIGHBORS, NO_NEIGHBOR, PatchCold, PatchHot, PatchUnpacked};
use pointray_patches::PatchSet;
use pointray_patches::patch_tiles::tile_ranges;
use pointray_scene::{BufferLayout, Material};
use rayon::prelude::*;

use crate::acceleration::{AccelerationStructure, BlasLayout, aabb_input, build, build_peak, build_sizes};
use crate::buffer::{Buffer, build_input_usage, storage_usage};
use crate::color_halo::{ColorHalo, NO_HALO};
use crate::context::GpuContext;
use crate::error::VulkanError;
use crate::gpu_records::{ObjectRecord, PatchCombined};
use crate::memory_plan::GpuLedger;
use crate::prepared_scene::{PreparedObject, SceneLayout};
use pointray_scene::HotRecords;

/// Bytes of one patch box (`VkAabbPositionsKHR`).
const BOX_BYTES: u64 = size_of::<Aabb>() as u64;

/// Whether a trace of a point set with `material` reads its cold records and colour
/// neighbours: only to colour hits by the points, so for the others they stay in memory.
pub(crate) fn reads_point_colors(material: &Material) -> bool {
    material.use_point_colors
}

/// A point set of more patches than this is cut into bottom levels of at most
/// `LARGE_SET_TILE_PATCHES`, whatever the device allows. Measured on an H100 at 1920x1080
/// (bench/RESULTS.md, "A billion points in bottom levels of 16M patches"): a billion patches
/// trace in 6.6 ms a frame in 60 bottom levels of 16M, in 10.1 ms in 16 of 64M and in 17.6 ms
/// in two of 500M, and five sets of 200M in 10.8 ms in 16M tiles against 12.7 ms whole; but
/// 100M patches trace in 2.75 ms in one bottom level and in 3.11 ms in six.
const ONE_BLAS_MOST_PATCHES: usize = 1 << 27;
const LARGE_SET_TILE_PATCHES: u32 = (1 << 24) - 1;

/// The tiles of `patches` for a device whose BLASes hold at most `max_tile_patches`, in
/// tiles of at most `LARGE_SET_TILE_PATCHES` for sets past `ONE_BLAS_MOST_PATCHES`.
pub(crate) fn patch_tiles(patches: &PatchSet, max_tile_patches: u32) -> Vec<Range<usize>> {
    tile_ranges(patches.len(), tile_size(patches.len(), max_tile_patches) as usize)
}

/// The most patches one tile of a set of `patch_count` holds where BLASes hold at most
/// `max_tile_patches`.
fn tile_size(patch_count: usize, max_tile_patches: u32) -> u32 {
    if patch_count > ONE_BLAS_MOST_PATCHES {
        max_tile_patches.min(LARGE_SET_TILE_PATCHES)
    } else {
        max_tile_patches
    }
}

pub(crate) fn prepare_patches(
    context: &Arc<GpuContext>,
    patches: &PatchSet,
    material: &Material,
    layout: SceneLayout,
    max_tile_patches: u32,
    ledger: &mut GpuLedger,
) -> Result<PreparedObject, VulkanError> {
    check_patch_set(patches)?;
    let count = patches.len();
    let colors = reads_point_colors(material).then_some(&NO_HALO);
    let records = record_bytes(patches, material, layout.buffers, layout.hot_records);
    let started = Instant::now();
    let bottom_levels = tile_bottom_levels(context, patches, layout, max_tile_patches, records, ledger)?;
    let what = format!("built {} bottom levels over {count} patches (boxes uploaded)", bottom_levels.len());
    log_phase(&what, count as u64 * BOX_BYTES, started.elapsed());
    ledger.check(records, "uploading the patch records")?;
    let started = Instant::now();
    let (record, buffers) =
        patch_records(context, patches, 0..count, layout.buffers, layout.hot_records, colors)?;
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

/// One BLAS per tile, each with its patches, built before the set's `records` bytes are
/// uploaded. Each tile's boxes are uploaded for its build alone: the structure keeps its own
/// copy and no shader reads them.
fn tile_bottom_levels(
    context: &Arc<GpuContext>,
    patches: &PatchSet,
    layout: SceneLayout,
    max_tile_patches: u32,
    records: u64,
    ledger: &mut GpuLedger,
) -> Result<Vec<(AccelerationStructure, Range<usize>)>, VulkanError> {
    let tiles = patch_tiles(patches, max_tile_patches);
    let count = tiles.len();
    let mut bottom_levels = Vec::with_capacity(count);
    for (index, tile) in tiles.into_iter().enumerate() {
        let (size, scratch) = build_sizes(context, &aabb_input(0, tile.len(), layout.blas));
        let transient = build_peak(tile_box_bytes(&tile, layout.blas), size, scratch);
        // The records come after the last build, so a build that leaves no room for them fails now.
        let step =
            format!("building bottom level {} of {count} (and the patch records after the last)", index + 1);
        ledger.check(transient.max(records), &step)?;
        let blas = tile_blas(context, patches, tile.clone(), layout.blas)?;
        ledger.hold_structure(&blas, tile_box_bytes(&tile, layout.blas));
        bottom_levels.push((blas, tile));
    }
    Ok(bottom_levels)
}

/// The bottom level of the patches in `tile`, built from their boxes, which are uploaded for
/// the build alone: the structure keeps its own copy and no shader reads them.
pub(crate) fn tile_blas(
    context: &Arc<GpuContext>,
    patches: &PatchSet,
    tile: Range<usize>,
    layout: BlasLayout,
) -> Result<AccelerationStructure, VulkanError> {
    let count = tile.len();
    let boxes = tile_boxes(&patches.aabbs[tile], layout);
    let boxes =
        Buffer::device_with_data(context, "patch boxes", bytemuck::cast_slice(&boxes), build_input_usage())?;
    build(context, &aabb_input(boxes.device_address(), count, layout))
}

/// The boxes of a tile's bottom level: each patch's own, or in `BlasLayout::PatchGroups` the
/// union of each run of patches, counted from the tile's first.
fn tile_boxes(patch_boxes: &[Aabb], layout: BlasLayout) -> Cow<'_, [Aabb]> {
    match layout.patches_per_box() as usize {
        1 => Cow::Borrowed(patch_boxes),
        run => Cow::Owned(
            patch_boxes
                .par_chunks(run)
                .map(|group| group.iter().skip(1).fold(group[0], |bounds, patch| bounds.union(patch)))
                .collect(),
        ),
    }
}

/// The per-patch records of the patches in `range` that the trace reads, in `buffers'`
/// layout only: the hot buffer (and the cold one where the trace colours hits by the
/// points), or the combined one. The colour blend walks the split hot and cold buffers
/// (`interpolate_color`), so where the trace colours hits by the points the combined layout
/// uploads them too, with the neighbour lists.
///
/// The shaders index every buffer by the patch's index in the whole set, so the addresses
/// recorded for a range are its buffers' less the range's start: a set uploaded a tile at
/// a time (`tile_stream`) is then read as one uploaded whole is. `colors` is the range's
/// colour halo (`color_halo`) where the trace colours hits by the points, else `None`; the
/// halo's records and neighbour lists follow the range's own.
pub(crate) fn patch_records(
    context: &Arc<GpuContext>,
    patches: &PatchSet,
    range: Range<usize>,
    buffers: BufferLayout,
    hot_records: HotRecords,
    colors: Option<&ColorHalo>,
) -> Result<(ObjectRecord, Vec<Buffer>), VulkanError> {
    let mut uploaded = Vec::new();
    let mut hold = |buffer: Buffer, stride: usize| {
        let address = buffer.device_address().wrapping_sub((range.start * stride) as u64);
        uploaded.push(buffer);
        address
    };
    let upload = |name, bytes: &[u8]| Buffer::device_with_data(context, name, bytes, storage_usage());
    let halo = colors.unwrap_or(&NO_HALO);
    let colors = colors.is_some();
    let lists = colors && !patches.color_neighbors.is_empty();
    let mut record = ObjectRecord::default();
    if buffers == BufferLayout::Split || colors {
        let hot = halo.records(&patches.hot, range.clone());
        record.hot = match hot_records {
            HotRecords::Packed => {
                hold(upload("hot patch records", bytemuck::cast_slice(&hot))?, size_of::<PatchHot>())
            }
            HotRecords::Unpacked => hold(unpacked_records(context, &hot)?, size_of::<PatchUnpacked>()),
        };
    }
    if colors {
        let cold = halo.records(&patches.cold, range.clone());
        record.cold =
            hold(upload("cold patch records", bytemuck::cast_slice(&cold))?, size_of::<PatchCold>());
    }
    if buffers == BufferLayout::Combined {
        let combined: Vec<PatchCombined> = patches.hot[range.clone()]
            .iter()
            .zip(&patches.cold[range.clone()])
            .map(|(&hot, &cold)| PatchCombined::new(hot, cold))
            .collect();
        let combined = bytemuck::cast_slice(&combined);
        record.combined = hold(upload("combined patch records", combined)?, size_of::<PatchCombined>());
    }
    // Only coloured clouds carry neighbour lists; the others keep address 0, which the
    // closest-hit shader never dereferences.
    if lists {
        let lists = halo.neighbor_lists(patches, range.clone());
        let stride = COLOR_NEIGHBORS * size_of::<u32>();
        record.color_neighbors =
            hold(upload("colour neighbour lists", bytemuck::cast_slice(&lists))?, stride);
    }
    Ok((record, uploaded))
}

/// `hot` unpacked (`HotRecords::Unpacked`) into a new device buffer, a staging buffer's worth
/// at a time: a large set's unpacked records would take twice its packed ones on the host.
fn unpacked_records(context: &Arc<GpuContext>, hot: &[PatchHot]) -> Result<Buffer, VulkanError> {
    const PIECE_RECORDS: usize = (32 << 20) / size_of::<PatchUnpacked>();
    let pieces = hot
        .chunks(PIECE_RECORDS)
        .map(|piece| piece.par_iter().map(PatchUnpacked::from).collect::<Vec<PatchUnpacked>>());
    let size = (hot.len() * size_of::<PatchUnpacked>()) as u64;
    Buffer::device_from_pieces(context, "unpacked hot patch records", size, storage_usage(), pieces)
}

/// The GPU bytes of the records a trace of `patches` with `material` reads.
pub(crate) fn record_bytes(
    patches: &PatchSet,
    material: &Material,
    buffers: BufferLayout,
    hot_records: HotRecords,
) -> u64 {
    let colors = reads_point_colors(material).then_some(&NO_HALO);
    range_record_bytes(patches, 0..patches.len(), buffers, hot_records, colors)
}

/// The GPU bytes of the records of the patches in `range` that a trace reads: with `colors`,
/// the range's colour halo where it colours hits by the points (as `patch_records`), those
/// of the halo too.
pub(crate) fn range_record_bytes(
    patches: &PatchSet,
    range: Range<usize>,
    buffers: BufferLayout,
    hot_records: HotRecords,
    colors: Option<&ColorHalo>,
) -> u64 {
    let own = range.len() as u64;
    let hot = hot_records.bytes_per_patch() as u64;
    let cold = size_of::<PatchCold>() as u64;
    let count = own + colors.map_or(0, ColorHalo::len) as u64;
    let colors = colors.is_some();
    let lists = colors && !patches.color_neighbors.is_empty();
    let neighbors = if lists { count * (COLOR_NEIGHBORS * size_of::<u32>()) as u64 } else { 0 };
    let split = match (buffers, colors) {
        (_, true) => count * (hot + cold),
        (BufferLayout::Split, false) => count * hot,
        (BufferLayout::Combined, false) => 0,
    };
    let combined =
        if buffers == BufferLayout::Combined { own * size_of::<PatchCombined>() as u64 } else { 0 };
    neighbors + split + combined
}

/// The build input of one tile: its boxes in `layout`.
pub(crate) fn tile_box_bytes(tile: &Range<usize>, layout: BlasLayout) -> u64 {
    layout.boxes(tile.len()) as u64 * BOX_BYTES
}

/// Refuses a patch set whose sections disagree, which the shaders would read past.
pub(crate) fn check_patch_set(patches: &PatchSet) -> Result<(), VulkanError> {
    let count = patches.len();
    if patches.aabbs.len() != count || patches.cold.len() != count {
        return Err(VulkanError::InvalidScene(format!(
            "a patch set has {} hot records, {} cold records and {} boxes; they must match",
            count,
            patches.cold.len(),
            patches.aabbs.len()
        )));
    }
    check_color_neighbors(patches)
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
    // Six lists a patch: billions of entries for the largest sets.
    match neighbors.par_iter().position_first(|&j| j != NO_NEIGHBOR && j as usize >= count) {
        Some(bad) => Err(VulkanError::InvalidScene(format!(
            "patch {} names colour neighbour {}, but the set has {count} patches",
            bad / COLOR_NEIGHBORS,
            neighbors[bad]
        ))),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_sets_past_the_one_blas_size_are_cut_into_smaller_tiles_than_the_device_allows() {
        let device = (1 << 29) - 1;
        assert_eq!(tile_size(100_000_000, device), device);
        assert_eq!(tile_size(ONE_BLAS_MOST_PATCHES, device), device);
        assert_eq!(tile_size(ONE_BLAS_MOST_PATCHES + 1, device), LARGE_SET_TILE_PATCHES);
        assert_eq!(tile_size(1_000_000_000, device), LARGE_SET_TILE_PATCHES);
        assert_eq!(tile_size(1_000_000_000, 1000), 1000, "a smaller limit still holds");
        assert_eq!(tile_ranges(1_000_000_000, tile_size(1_000_000_000, device) as usize).len(), 60);
    }
}
