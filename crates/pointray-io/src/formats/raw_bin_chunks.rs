//! Raw LiDAR sweeps (`.bin`, KITTI or nuScenes) read in chunks of records (`point_stream`),
//! with the whole read's checks: the layout the name implies must divide the file and every
//! record must be plausible in it, else the same error names what each layout makes of the
//! file. Intensities are scaled by the whole file's range, learnt by the survey.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use super::intensity::IntensityRange;
use super::raw_bin::{SweepLayout, column_rows, misread, plausible, whole_records};
use crate::{AttributeBytes, IoError, PointCloud};

/// Records checked at a time when a misread file is read again in the other layout.
const CHECK_RECORDS: usize = 1 << 16;

pub(crate) struct RawBinChunks {
    path: PathBuf,
    reader: BufReader<File>,
    layout: SweepLayout,
    count: u64,
    read: u64,
}

impl RawBinChunks {
    /// Opens a sweep in the layout its name implies; a length that is not whole records of
    /// it is refused as the whole read refuses it.
    pub(crate) fn open(path: &Path) -> Result<Self, IoError> {
        let file = File::open(path).map_err(|e| IoError::os(path, e))?;
        let length = file.metadata().map_err(|e| IoError::os(path, e))?.len();
        let layout = SweepLayout::named_by(path);
        let width = layout.record_bytes() / 4;
        if let Err(problem) = whole_records(length as usize, width) {
            let other = layout.other();
            return Err(misread(
                path,
                layout,
                problem,
                whole_records(length as usize, other.record_bytes() / 4),
            ));
        }
        let count = length / layout.record_bytes() as u64;
        Ok(Self { path: path.to_path_buf(), reader: BufReader::new(file), layout, count, read: 0 })
    }

    /// The attributes the chunks carry.
    pub(crate) fn attributes(&self) -> AttributeBytes {
        let rings = self.layout == SweepLayout::NuScenes;
        AttributeBytes { intensities: true, rings, ..Default::default() }
    }

    pub(crate) fn declared_points(&self) -> u64 {
        self.count
    }

    pub(crate) fn rewind(&mut self) -> Result<(), IoError> {
        self.reader.seek(SeekFrom::Start(0)).map_err(|e| IoError::os(&self.path, e))?;
        self.read = 0;
        Ok(())
    }

    /// Up to `max` more points, or `None` at the end. A survey widens `range` by their
    /// intensities and returns positions only; otherwise intensities are scaled by `range`.
    pub(crate) fn next(
        &mut self,
        max: usize,
        range: &mut IntensityRange,
        survey: bool,
    ) -> Result<Option<PointCloud>, IoError> {
        let count = (self.count - self.read).min(max.max(1) as u64) as usize;
        if count == 0 {
            return Ok(None);
        }
        let mut bytes = vec![0u8; count * self.layout.record_bytes()];
        self.reader.read_exact(&mut bytes).map_err(|e| IoError::os(&self.path, e))?;
        let first = self.read;
        self.read += count as u64;
        if let Err(problem) = plausible(&bytes, self.layout, first) {
            let as_other = plausible_file(&self.path, self.layout.other());
            return Err(misread(&self.path, self.layout, problem, as_other));
        }
        let malformed = |problem| IoError::malformed(&self.path, problem);
        let rows = column_rows(&bytes, &self.layout.spec(), first).map_err(malformed)?;
        let cloud = if survey {
            rows.include_intensities(range);
            PointCloud::from_positions(
                rows.into_point_cloud_scaled(&IntensityRange::default()).map_err(malformed)?.positions,
            )
        } else {
            rows.into_point_cloud_scaled(range).map_err(malformed)?
        };
        Ok(Some(PointCloud { sensor_position: Some(glam::DVec3::ZERO), ..cloud }))
    }
}

/// Whether the whole file reads plausibly in `layout`, checked a part at a time.
fn plausible_file(path: &Path, layout: SweepLayout) -> Result<(), String> {
    let mut file = File::open(path).map_err(|e| e.to_string())?;
    let length = file.metadata().map_err(|e| e.to_string())?.len();
    whole_records(length as usize, layout.record_bytes() / 4)?;
    let mut bytes = vec![0u8; CHECK_RECORDS * layout.record_bytes()];
    let mut first = 0u64;
    loop {
        let read = read_full(&mut file, &mut bytes).map_err(|e| e.to_string())?;
        if read == 0 {
            return Ok(());
        }
        plausible(&bytes[..read], layout, first)?;
        first += (read / layout.record_bytes()) as u64;
    }
}

fn read_full(file: &mut File, buffer: &mut [u8]) -> std::io::Result<usize> {
    let mut filled = 0;
    while filled < buffer.len() {
        match file.read(&mut buffer[filled..])? {
            0 => break,
            read => filled += read,
        }
    }
    Ok(filled)
}
