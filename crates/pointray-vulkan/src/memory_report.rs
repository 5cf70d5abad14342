//! What a prepared scene cost to build and holds in GPU memory (the benchmark's "costs").

use std::time::Duration;

use crate::acceleration::AccelerationStructure;
use crate::prepared_scene::PreparedScene;
use pointray_scene::HotRecords;

/// Build times and memory of a prepared scene's acceleration structures and buffers.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BuildReport {
    /// Bottom levels built: one per mesh and per tile of a point set.
    pub blas_count: usize,
    /// Sum of the bottom levels' build wall times, compaction included.
    pub blas_build: Duration,
    pub tlas_build: Duration,
    /// GPU bytes of the bottom levels (after compaction) and of the top level.
    pub blas_bytes: u64,
    pub tlas_bytes: u64,
    /// GPU bytes of the buffers the traces read: the hot (or the combined) patch records,
    /// the cold ones and colour neighbour lists where a material colours hits by the
    /// points, mesh vertices and indices, the background's environment map and the emissive
    /// triangles' table. The build inputs (patch
    /// boxes, TLAS instances) are freed once built.
    pub geometry_bytes: u64,
    /// The most GPU memory the buffers and structures took at once while the scene was
    /// built (build inputs and scratch included; the frame's images are not).
    pub peak_build_bytes: u64,
    /// Consecutive patches one box of the point sets' bottom levels bounds.
    pub patches_per_box: u32,
    /// The form of the point sets' hot records.
    pub hot_records: HotRecords,
}

impl BuildReport {
    /// Everything the scene keeps on the GPU: buffers and acceleration structures.
    pub fn gpu_bytes(&self) -> u64 {
        self.geometry_bytes + self.blas_bytes + self.tlas_bytes
    }
}

impl PreparedScene {
    /// What building this scene took and what it occupies; a streamed scene's resident
    /// tiles count as built, and its peak is the most its tiles held at once beside a top
    /// level over all of them.
    pub fn build_report(&self) -> BuildReport {
        let tiles = self.streaming.iter().flat_map(|streaming| streaming.tiles.resident.values());
        let bottom_levels: Vec<&AccelerationStructure> =
            self._bottom_levels.iter().chain(tiles.clone().map(|tile| &tile.blas)).collect();
        let buffers = self._geometry.iter().chain(tiles.flat_map(|tile| &tile.buffers));
        BuildReport {
            blas_count: bottom_levels.len(),
            blas_build: bottom_levels.iter().map(|b| b.build_time).sum(),
            tlas_build: self.tlas.build_time,
            blas_bytes: bottom_levels.iter().map(|b| b.size()).sum(),
            tlas_bytes: self.tlas.size(),
            patches_per_box: self.blas_layout.patches_per_box(),
            hot_records: self.hot_records,
            peak_build_bytes: self.streaming.as_ref().map_or(self.build_peak, |streaming| {
                self.build_peak.max(streaming.beside_tiles + streaming.tiles.peak)
            }),
            geometry_bytes: buffers.map(|b| b.size).sum::<u64>()
                + [&self.environment, &self.emissive]
                    .iter()
                    .filter_map(|table| table.as_ref())
                    .map(|table| table.bytes())
                    .sum::<u64>(),
        }
    }
}
