//! LAS and LAZ read in batches (`point_stream`): a first pass takes the positions and the
//! ranges that scale colours, intensities and classifications (the whole file's, as the
//! whole read takes them), a second the points with their attributes so scaled.

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use glam::DVec3;
use las::{PointData, PointDataBuilder};

use super::copc::is_copc;
use super::copc_chunks::CopcBatches;
use super::intensity::IntensityRange;
use super::las::{batch_points, color_shift, las_error, open_reader, survive_decoder};
use crate::{AttributeBytes, IoError, PointCloud};

/// What the first pass learns of the whole file's attributes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct LasRanges {
    intensities: IntensityRange,
    largest_color: Option<u16>,
    any_classification: bool,
}

pub(crate) struct LasChunks {
    path: PathBuf,
    decoder: Decoder,
    declared: u64,
    read: u64,
}

/// Where the batches come from.
enum Decoder {
    /// LAS and LAZ, decoded in order.
    InOrder { reader: las::Reader, batch: PointData },
    /// COPC, whose chunks are decoded in parallel.
    Copc(Box<CopcBatches>),
}

impl LasChunks {
    pub(crate) fn open(path: &Path) -> Result<Self, IoError> {
        let decoder = if is_copc_file(path)? {
            Decoder::Copc(Box::new(CopcBatches::open(path)?))
        } else {
            let reader = open_reader(path)?;
            let batch = PointDataBuilder::new().for_header(reader.header()).build();
            Decoder::InOrder { reader, batch }
        };
        let declared = decoder.header().number_of_points();
        Ok(Self { path: path.to_path_buf(), decoder, declared, read: 0 })
    }

    pub(crate) fn declared_points(&self) -> u64 {
        self.declared
    }

    /// Whether the file is COPC, whose octree may be walked instead (`copc_octree`).
    pub(crate) fn is_copc(&self) -> bool {
        matches!(self.decoder, Decoder::Copc(_))
    }

    /// The attributes the chunks may carry (intensities and classifications are dropped
    /// later when the file never fills them).
    pub(crate) fn attributes(&self) -> AttributeBytes {
        let format = self.decoder.header().point_format();
        AttributeBytes {
            colors: format.has_color,
            intensities: true,
            classifications: true,
            ..Default::default()
        }
    }

    /// Back to the first point, for the next pass.
    pub(crate) fn rewind(&mut self) -> Result<(), IoError> {
        *self = Self::open(&self.path)?;
        Ok(())
    }

    /// Up to `max` more points (fewer when the reader's batch is smaller), or `None` at the
    /// end; `ranges` grows with them when `survey` is
    /// set, and scales them otherwise.
    pub(crate) fn next(
        &mut self,
        max: usize,
        ranges: &mut LasRanges,
        survey: bool,
    ) -> Result<Option<PointCloud>, IoError> {
        let Some(batch) = self.decoder.next(&self.path, max.max(1) as u64)? else {
            return self.check_count().map(|()| None);
        };
        self.read += batch.len() as u64;
        let positions: Vec<DVec3> =
            batch.x().zip(batch.y()).zip(batch.z()).map(|((x, y), z)| DVec3::new(x, y, z)).collect();
        if survey {
            ranges.include(batch);
            return Ok(Some(PointCloud::from_positions(positions)));
        }
        Ok(Some(ranges.scaled(batch, positions)))
    }

    fn check_count(&self) -> Result<(), IoError> {
        if self.read == self.declared {
            return Ok(());
        }
        let problem = format!("header declares {} points but the data holds {}", self.declared, self.read);
        Err(IoError::malformed(&self.path, problem))
    }
}

impl Decoder {
    fn header(&self) -> &las::Header {
        match self {
            Self::InOrder { reader, .. } => reader.header(),
            Self::Copc(batches) => batches.header(),
        }
    }

    /// The next batch of at most `max` points, `None` at the end.
    fn next(&mut self, path: &Path, max: u64) -> Result<Option<&PointData>, IoError> {
        match self {
            Self::InOrder { reader, batch } => {
                let wanted = batch_points(reader.header()).min(max);
                let read = survive_decoder(path, || {
                    reader.fill_points(wanted, batch).map_err(|e| las_error(path, e))
                })?;
                Ok((read > 0).then_some(&*batch))
            }
            Self::Copc(batches) => batches.next(max),
        }
    }
}

/// Whether the LAS file at `path` is COPC.
fn is_copc_file(path: &Path) -> Result<bool, IoError> {
    let file = File::open(path).map_err(|source| IoError::os(path, source))?;
    Ok(is_copc(&mut BufReader::new(file)))
}

impl LasRanges {
    pub(super) fn include(&mut self, batch: &PointData) {
        batch.intensity().for_each(|value| self.intensities.include(value.into()));
        self.any_classification |= batch.classification().any(|class| class != 0);
        if let Some(rgb) = batch.rgb() {
            let largest = rgb.map(|(r, g, b)| r.max(g).max(b)).max().unwrap_or(0);
            self.largest_color = Some(self.largest_color.unwrap_or(0).max(largest));
        }
    }

    /// Widens these ranges by `other`'s.
    pub(super) fn join(&mut self, other: &LasRanges) {
        if let Some((low, high)) = other.intensities.bounds() {
            self.intensities.include(low);
            self.intensities.include(high);
        }
        self.any_classification |= other.any_classification;
        self.largest_color = self.largest_color.max(other.largest_color);
    }

    /// Whether attributes scaled by these ranges and by `other` come out the same.
    pub(super) fn scales_as(&self, other: &LasRanges) -> bool {
        self.intensities.scale() == other.intensities.scale()
            && self.largest_color.and_then(color_shift) == other.largest_color.and_then(color_shift)
            && self.any_classification == other.any_classification
    }

    /// The batch's points with attributes scaled as a whole read of the file scales them.
    pub(super) fn scaled(&self, batch: &PointData, positions: Vec<DVec3>) -> PointCloud {
        let intensities =
            self.intensities.scale().map(|scale| batch.intensity().map(|v| scale.apply(v.into())).collect());
        let shift = self.largest_color.and_then(color_shift);
        let colors = shift.and_then(|shift| {
            let rgb = batch.rgb()?;
            Some(rgb.map(|(r, g, b)| [r, g, b].map(|channel| (channel >> shift) as u8)).collect())
        });
        PointCloud {
            intensities,
            colors,
            classifications: self.any_classification.then(|| batch.classification().collect()),
            ..PointCloud::from_positions(positions)
        }
    }
}
