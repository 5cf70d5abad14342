//! A cloud sorted along its curve once and kept in a folder, so that tile jobs
//! (`streamed_prep::prep_one_tile` on it) read their tiles without each reading and sorting
//! the whole cloud again. The folder holds the sorted records (`points`) and an index
//! (`index`): the cloud's box, its recentring, the records' layout, the sensor's position, the
//! curve the records are sorted along and the bounds of every block of records. Jobs cut the same tiles from it as from the input.

use std::path::Path;

use glam::{DVec3, Vec3};
use pointray_io::temporaries::TemporaryFolder;
use pointray_io::{IoError, MemoryBudget, PointStream};
use pointray_patches::PrepSettings;

use crate::morton::MortonGrid;
use crate::prep_progress::PrepProgress;
use crate::tiles::disk_room::{ensure_room, sorted_points_need};
use crate::tiles::point_records::RecordLayout;
use crate::tiles::sorted_points::{BlockBounds, SortedPoints};
use crate::tiles::stream_error::StreamError;
use crate::tiles::streamed_tiles::{CloudBox, StreamPlan, TileCount};

const RECORDS: &str = "points";
const INDEX: &str = "index";
const MAGIC: [u8; 8] = *b"PRSORT02";

/// Bytes of the index before the block bounds: the magic, the layout's flags, the point
/// count, the offset, the box, the sensor's position (with a flag) and the curve's grid
/// (its corner and scale).
const HEAD_BYTES: usize = 8 + 8 + 8 + 3 * 8 + 6 * 8 + 8 + 3 * 8 + 4 * 8;

/// Bytes of one block's bounds.
const BLOCK_BYTES: usize = 6 * 4;

/// Sorts `stream` within `memory` and keeps the sort in the new folder `output`; returns
/// how many points it holds. The sort is made in a scratch folder beside `output` and moved
/// into place, so a folder with an index is always whole.
pub fn keep_sort(
    stream: &mut PointStream,
    settings: &PrepSettings,
    memory: MemoryBudget,
    output: &Path,
    progress: &dyn PrepProgress,
) -> Result<u64, StreamError> {
    if output.exists() {
        return Err(IoError::unwritable(output, "already exists; a sort is kept in a new folder").into());
    }
    let folder = pointray_io::folder_of(output);
    ensure_room(&[sorted_points_need(stream, folder)])?;
    let scratch = TemporaryFolder::new_in(folder)?;
    let plan = StreamPlan::new(stream, settings, (TileCount::AtLeast(1), memory), scratch.path(), progress)?;
    let cloud = plan.cloud_box();
    let sorted = plan.into_sorted();
    let index = index_bytes(&cloud, &sorted);
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| StreamError::Io(IoError::os(path, source))
    };
    std::fs::create_dir(output).map_err(io(output))?;
    std::fs::rename(sorted.path(), output.join(RECORDS)).map_err(io(output))?;
    pointray_io::write_atomically(&output.join(INDEX), |out| std::io::Write::write_all(out, &index))?;
    Ok(cloud.points)
}

/// The plan of a sort kept in `folder`, cut into `count` tiles within `memory`.
pub(crate) fn open_kept(
    folder: &Path,
    settings: &PrepSettings,
    (count, memory): (TileCount, MemoryBudget),
) -> Result<StreamPlan, StreamError> {
    let malformed = |problem: String| StreamError::BadTile {
        path: folder.to_path_buf(),
        problem: format!("not a sort `prep --keep-sort` kept: {problem}"),
    };
    let index = std::fs::read(folder.join(INDEX)).map_err(|e| malformed(format!("its index: {e}")))?;
    let (cloud, layout, sensor, blocks) = read_index(&index).map_err(malformed)?;
    let records = folder.join(RECORDS);
    let sorted = SortedPoints::reopen(&records, (layout, cloud.offset, cloud.points), blocks, sensor)
        .map_err(|problem| malformed(format!("{}: {problem}", records.display())))?;
    StreamPlan::of_kept(folder, (cloud, sorted), settings, (count, memory))
}

/// Whether `path` is a folder that holds a kept sort's index.
pub fn is_kept_sort(path: &Path) -> bool {
    path.join(INDEX).is_file()
}

fn index_bytes(cloud: &CloudBox, sorted: &SortedPoints) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEAD_BYTES + sorted.blocks().len() * BLOCK_BYTES);
    let put_vector =
        |out: &mut Vec<u8>, v: DVec3| v.to_array().iter().for_each(|x| out.extend(x.to_le_bytes()));
    out.extend(MAGIC);
    out.extend(u64::from(sorted.layout().flags()).to_le_bytes());
    out.extend(cloud.points.to_le_bytes());
    put_vector(&mut out, cloud.offset);
    put_vector(&mut out, cloud.bounds.0);
    put_vector(&mut out, cloud.bounds.1);
    out.extend(u64::from(sorted.sensor_position().is_some()).to_le_bytes());
    put_vector(&mut out, sorted.sensor_position().unwrap_or(DVec3::ZERO));
    let (corner, scale) = cloud.grid.parts();
    put_vector(&mut out, corner.as_dvec3());
    out.extend(f64::from(scale).to_le_bytes());
    for (low, high) in sorted.blocks() {
        [low, high].iter().for_each(|v| v.to_array().iter().for_each(|x| out.extend(x.to_le_bytes())));
    }
    out
}

type Index = (CloudBox, RecordLayout, Option<DVec3>, Vec<BlockBounds>);

fn read_index(bytes: &[u8]) -> Result<Index, String> {
    if bytes.len() < HEAD_BYTES || bytes[..8] != MAGIC {
        return Err("its index is not one this version of pointray reads; keep the sort again".into());
    }
    let words: Vec<[u8; 8]> =
        bytes[8..HEAD_BYTES].chunks_exact(8).map(|w| w.try_into().expect("8 bytes")).collect();
    let float = |i: usize| f64::from_le_bytes(words[i]);
    let vector = |i: usize| DVec3::new(float(i), float(i + 1), float(i + 2));
    let flags = u64::from_le_bytes(words[0]);
    let layout = u8::try_from(flags).ok().and_then(RecordLayout::of_flags).ok_or("its layout is unknown")?;
    let points = u64::from_le_bytes(words[1]);
    let (offset, min, max) = (vector(2), vector(5), vector(8));
    let sensor = (u64::from_le_bytes(words[11]) != 0).then(|| vector(12));
    let (corner, scale) = (vector(15), float(18));
    let finite = [offset, min, max, sensor.unwrap_or(DVec3::ZERO), corner].iter().all(|v| v.is_finite());
    if !finite || min.cmpgt(max).any() || !(scale.is_finite() && scale > 0.0) {
        return Err("its box, offset or curve is not finite and ordered".into());
    }
    let grid = MortonGrid::from_parts(corner.as_vec3(), scale as f32);
    let body = &bytes[HEAD_BYTES..];
    if !body.len().is_multiple_of(BLOCK_BYTES) {
        return Err("its block bounds are cut short".into());
    }
    let blocks = body
        .chunks_exact(BLOCK_BYTES)
        .map(|block| {
            let value = |i: usize| f32::from_le_bytes(block[4 * i..4 * i + 4].try_into().expect("4 bytes"));
            (Vec3::new(value(0), value(1), value(2)), Vec3::new(value(3), value(4), value(5)))
        })
        .collect();
    Ok((CloudBox { bounds: (min, max), offset, points, grid }, layout, sensor, blocks))
}
