//! LAS and LAZ read in batches (`point_stream`): a first pass takes the positions and the
//! ranges that scale colours, intensities and classifications (the whole file's, as the
//! whole read takes them), a second the points with their attributes so scaled.

use std::path::{Path, PathBuf};

use glam::DVec3;
use las::{PointData, PointDataBuilder};

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
    reader: las::Reader,
    batch: PointData,
    declared: u64,
    read: u64,
}

impl LasChunks {
    pub(crate) fn open(path: &Path) -> Result<Self, IoError> {
        let reader = open_reader(path)?;
        let declared = reader.header().number_of_points();
        let batch = PointDataBuilder::new().for_header(reader.header()).build();
        Ok(Self { path: path.to_path_buf(), reader, batch, declared, read: 0 })
    }

    pub(crate) fn declared_points(&self) -> u64 {
        self.declared
    }

    /// The attributes the chunks may carry (intensities and classifications are dropped
    /// later when the file never fills them).
    pub(crate) fn attributes(&self) -> AttributeBytes {
        let format = self.reader.header().point_format();
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
    /// end; `ranges` grows with them when `survey` is set, and scales them otherwise.
    pub(crate) fn next(
        &mut self,
        max: usize,
        ranges: &mut LasRanges,
        survey: bool,
    ) -> Result<Option<PointCloud>, IoError> {
        let Self { path, reader, batch, .. } = self;
        let wanted = batch_points(reader.header()).min(max.max(1) as u64);
        let read =
            survive_decoder(path, || reader.fill_points(wanted, batch).map_err(|e| las_error(path, e)))?;
        self.read += read;
        if read == 0 {
            return self.check_count().map(|()| None);
        }
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

impl LasRanges {
    fn include(&mut self, batch: &PointData) {
        batch.intensity().for_each(|value| self.intensities.include(value.into()));
        self.any_classification |= batch.classification().any(|class| class != 0);
        if let Some(rgb) = batch.rgb() {
            let largest = rgb.map(|(r, g, b)| r.max(g).max(b)).max().unwrap_or(0);
            self.largest_color = Some(self.largest_color.unwrap_or(0).max(largest));
        }
    }

    /// The batch's points with attributes scaled as a whole read of the file scales them.
    fn scaled(&self, batch: &PointData, positions: Vec<DVec3>) -> PointCloud {
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
