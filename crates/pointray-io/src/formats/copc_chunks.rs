//! A COPC file read in batches (`las_chunks`, for `point_stream`): runs of chunks in file
//! order, each run decoded in parallel, handed out a batch of at most the points asked for
//! at a time.

use std::path::Path;

use las::{PointData, PointDataBuilder};

use super::copc::CopcFile;
use crate::IoError;

pub(super) struct CopcBatches {
    file: CopcFile,
    /// The first chunk of the next run.
    next_chunk: usize,
    /// The point records of the run decoded last, and how many bytes of them were handed out.
    decoded: Vec<u8>,
    handed: usize,
    batch: PointData,
}

impl CopcBatches {
    pub(super) fn open(path: &Path) -> Result<Self, IoError> {
        let file = CopcFile::open(path)?;
        let batch = PointDataBuilder::new().for_header(file.header()).build();
        Ok(Self { file, next_chunk: 0, decoded: Vec::new(), handed: 0, batch })
    }

    pub(super) fn header(&self) -> &las::Header {
        self.file.header()
    }

    /// The next at most `max` points (at least 1), or `None` after the last.
    pub(super) fn next(&mut self, max: u64) -> Result<Option<&PointData>, IoError> {
        if self.handed == self.decoded.len() && !self.decode_run(max)? {
            return Ok(None);
        }
        let record = usize::from(self.header().point_format().len());
        let bytes =
            (self.decoded.len() - self.handed).min(usize::try_from(max).unwrap_or(usize::MAX) * record);
        let records = self.decoded[self.handed..self.handed + bytes].to_vec();
        self.handed += bytes;
        self.batch = PointDataBuilder::new()
            .for_header(self.file.header())
            .build_from_bytes(records)
            .map_err(|error| {
                IoError::malformed(self.file.path(), format!("COPC chunks do not split into points: {error}"))
            })?;
        Ok(Some(&self.batch))
    }

    /// Decodes the next chunks that together hold at most `max` points (at least one chunk);
    /// false after the last.
    fn decode_run(&mut self, max: u64) -> Result<bool, IoError> {
        let chunks = &self.file.chunks()[self.next_chunk..];
        let Some(first) = chunks.first() else { return Ok(false) };
        let mut points = chunk_points(first);
        let taken = 1 + chunks[1..]
            .iter()
            .take_while(|chunk| {
                points += chunk_points(chunk);
                points <= max
            })
            .count();
        let decoded = self.file.decode_each(&chunks[..taken])?;
        self.next_chunk += taken;
        self.decoded = decoded.iter().flat_map(|chunk| chunk.raw_bytes()).copied().collect();
        self.handed = 0;
        Ok(true)
    }
}

fn chunk_points(chunk: &las::copc::Entry) -> u64 {
    u64::try_from(chunk.point_count).unwrap_or(0)
}
