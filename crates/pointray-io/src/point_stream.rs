//! A point cloud read in chunks, so that a cloud larger than memory can be processed in
//! bounded memory. Two passes: `survey` yields the positions alone and learns the whole
//! file's attribute ranges (colour depth, intensity scale, whether classifications are
//! filled), which scale the attributes of the chunks `read` yields afterwards exactly as a
//! whole read of the file would. Binary PLY, LAS/LAZ and raw sweeps (`.bin`, in the layout
//! their name implies) are chunked; formats that cannot be (E57, text, PCD, ascii PLY, raw
//! sweeps given other columns) are read whole when the budget holds them.

use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::formats::copc_octree::CopcOctree;
use crate::formats::detect::PointFormat;
use crate::formats::intensity::IntensityRange;
use crate::formats::las_chunks::{LasChunks, LasRanges};
use crate::formats::ply::chunks::PlyChunks;
use crate::formats::raw_bin_chunks::RawBinChunks;
use crate::formats::{ColumnSpec, FileFormat, detect_file_format, read_point_cloud_with};
use crate::{IoError, MemoryBudget, PointCloud};

/// How many times its file size a cloud read whole may take in memory: text holds about
/// 30 bytes a point for the 24 of its f64 position, and compressed formats less.
const WHOLE_READ_EXPANSION: u64 = 4;

pub struct PointStream {
    path: PathBuf,
    source: Source,
    points: u64,
    /// Set by `survey`.
    ranges: Option<Ranges>,
}

enum Source {
    Ply(PlyChunks),
    Las(LasChunks),
    RawBin(RawBinChunks),
    /// A cloud that could not be chunked, handed out in chunks from memory.
    Whole {
        cloud: PointCloud,
        next: usize,
    },
}

/// The attribute ranges a survey learns.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
enum Ranges {
    #[default]
    None,
    Ply(f64),
    Las(LasRanges),
    RawBin(IntensityRange),
}

impl PointStream {
    /// Opens `path` for reading in chunks; `columns` as for `read_point_cloud_with`. A file
    /// that must be read whole is, when `budget` holds it, and is refused otherwise.
    pub fn open(path: &Path, columns: Option<&ColumnSpec>, budget: MemoryBudget) -> Result<Self, IoError> {
        let format = detect_file_format(path)?;
        let source = match (format, columns) {
            (FileFormat::Points(PointFormat::Ply), None) => PlyChunks::open(path)?.map(Source::Ply),
            (FileFormat::Points(PointFormat::Las | PointFormat::Laz), None) => {
                Some(Source::Las(LasChunks::open(path)?))
            }
            (FileFormat::Points(PointFormat::RawBin), None) => {
                Some(Source::RawBin(RawBinChunks::open(path)?))
            }
            _ => None,
        };
        let source = match source {
            Some(source) => source,
            None => Source::Whole { cloud: read_whole(path, format, columns, budget)?, next: 0 },
        };
        let points = match &source {
            Source::Ply(chunks) => chunks.declared_points(),
            Source::Las(chunks) => chunks.declared_points(),
            Source::RawBin(chunks) => chunks.declared_points(),
            Source::Whole { cloud, .. } => cloud.len() as u64,
        };
        Ok(Self { path: path.to_path_buf(), source, points, ranges: None })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The points the file declares.
    pub fn len(&self) -> u64 {
        self.points
    }

    pub fn is_empty(&self) -> bool {
        self.points == 0
    }

    /// Whether the file is read in chunks (rather than whole, into memory).
    pub fn is_chunked(&self) -> bool {
        !matches!(self.source, Source::Whole { .. })
    }

    /// The cloud of a file that was read whole, for a caller that preps it in memory and so
    /// need not read the file again (`None` for a file read in chunks).
    pub fn into_whole_cloud(self) -> Option<PointCloud> {
        match self.source {
            Source::Whole { cloud, .. } => Some(cloud),
            Source::Ply(_) | Source::Las(_) | Source::RawBin(_) => None,
        }
    }

    /// The bytes each point's attributes take once read (at most: a LAS file's unfilled
    /// fields are dropped).
    pub fn attribute_bytes_per_point(&self) -> u64 {
        match &self.source {
            Source::Ply(chunks) => chunks.attributes().per_point(),
            Source::Las(chunks) => chunks.attributes().per_point(),
            // Intensities; a nuScenes sweep's rings too.
            Source::RawBin(chunks) => chunks.attributes().per_point(),
            Source::Whole { cloud, .. } => cloud.attribute_bytes_per_point(),
        }
    }

    /// Where the scanner stood, when the file says so for the whole cloud.
    pub fn sensor_position(&self) -> Option<DVec3> {
        match &self.source {
            Source::Whole { cloud, .. } => cloud.sensor_position,
            // A raw sweep's records are in the sensor's own frame.
            Source::RawBin(_) => Some(DVec3::ZERO),
            Source::Ply(_) | Source::Las(_) => None,
        }
    }

    /// The octree of a COPC file read in chunks, with the top levels that hold at least
    /// `sample_points` points read (`CopcOctree::open`); `None` for any other source.
    pub fn copc_octree(&self, sample_points: u64) -> Result<Option<CopcOctree>, IoError> {
        match &self.source {
            Source::Las(chunks) if chunks.is_copc() => CopcOctree::open(&self.path, sample_points).map(Some),
            _ => Ok(None),
        }
    }

    /// The first pass: every point's position, in chunks of at most `max` points.
    pub fn survey<E: From<IoError>>(
        &mut self,
        max: usize,
        mut each: impl FnMut(&[DVec3]) -> Result<(), E>,
    ) -> Result<(), E> {
        let mut ranges = self.initial_ranges();
        self.rewind()?;
        while let Some(chunk) = self.next(max, &mut ranges, true)? {
            each(&chunk.positions)?;
        }
        self.ranges = Some(ranges);
        Ok(())
    }

    /// The points with their attributes, in chunks of at most `max` points; surveys first
    /// when that has not been done. `each` takes the chunks on a thread of its own while the
    /// next one is read, so at most three chunks are held at once.
    pub fn read<E: From<IoError> + Send>(
        &mut self,
        max: usize,
        each: impl FnMut(PointCloud) -> Result<(), E> + Send,
    ) -> Result<(), E> {
        if self.ranges.is_none() {
            self.survey(max, |_| Ok::<(), E>(()))?;
        }
        let mut ranges = self.ranges.unwrap_or_default();
        self.rewind()?;
        std::thread::scope(|scope| {
            let (sender, chunks) = std::sync::mpsc::sync_channel(1);
            let taker = scope.spawn(move || chunks.into_iter().try_for_each(each));
            let read = loop {
                match self.next(max, &mut ranges, false) {
                    // A closed channel means `each` failed: its error is the one to report.
                    Ok(Some(chunk)) => {
                        if sender.send(chunk).is_err() {
                            break Ok(());
                        }
                    }
                    Ok(None) => break Ok(()),
                    Err(error) => break Err(error),
                }
            };
            drop(sender);
            let handed = taker.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            handed?;
            Ok(read?)
        })
    }

    fn initial_ranges(&self) -> Ranges {
        match self.source {
            Source::Ply(_) => Ranges::Ply(0.0),
            Source::Las(_) => Ranges::Las(LasRanges::default()),
            Source::RawBin(_) => Ranges::RawBin(IntensityRange::default()),
            Source::Whole { .. } => Ranges::None,
        }
    }

    fn rewind(&mut self) -> Result<(), IoError> {
        match &mut self.source {
            Source::Ply(chunks) => chunks.rewind(),
            Source::Las(chunks) => chunks.rewind(),
            Source::RawBin(chunks) => chunks.rewind(),
            Source::Whole { next, .. } => {
                *next = 0;
                Ok(())
            }
        }
    }

    fn next(&mut self, max: usize, ranges: &mut Ranges, survey: bool) -> Result<Option<PointCloud>, IoError> {
        match (&mut self.source, ranges) {
            (Source::Ply(chunks), Ranges::Ply(largest)) => chunks.next(max, largest, survey),
            (Source::Las(chunks), Ranges::Las(ranges)) => chunks.next(max, ranges, survey),
            (Source::RawBin(chunks), Ranges::RawBin(range)) => chunks.next(max, range, survey),
            (Source::Whole { cloud, next }, _) => {
                let start = *next;
                let end = (start + max.max(1)).min(cloud.len());
                *next = end;
                Ok((start < end).then(|| slice_of(cloud, start, end)))
            }
            _ => unreachable!("ranges are made for their source"),
        }
    }
}

fn read_whole(
    path: &Path,
    format: FileFormat,
    columns: Option<&ColumnSpec>,
    budget: MemoryBudget,
) -> Result<PointCloud, IoError> {
    let length = std::fs::metadata(path).map_err(|e| IoError::os(path, e))?.len();
    if let Err(shortfall) = budget.check(length, WHOLE_READ_EXPANSION, "bytes of file") {
        let problem = format!(
            "a {} file cannot be read in chunks, and reading it whole does not fit the memory \
             budget ({shortfall}); convert it to LAS/LAZ or binary PLY, or raise the budget",
            format.name()
        );
        return Err(IoError::unusable(path, problem));
    }
    read_point_cloud_with(path, columns)
}

/// Points `start..end` of `cloud` with their attributes.
fn slice_of(cloud: &PointCloud, start: usize, end: usize) -> PointCloud {
    fn part<T: Clone>(values: &Option<Vec<T>>, start: usize, end: usize) -> Option<Vec<T>> {
        values.as_ref().map(|values| values[start..end].to_vec())
    }
    PointCloud {
        positions: cloud.positions[start..end].to_vec(),
        normals: part(&cloud.normals, start, end),
        colors: part(&cloud.colors, start, end),
        intensities: part(&cloud.intensities, start, end),
        classifications: part(&cloud.classifications, start, end),
        rings: part(&cloud.rings, start, end),
        sensor_origins: part(&cloud.sensor_origins, start, end),
        sensor_position: cloud.sensor_position,
    }
}
