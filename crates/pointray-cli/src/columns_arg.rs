//! `--columns`, shared by every command that reads points: what each column of a file that
//! does not name its columns holds (text points, raw `.bin` sweeps).

use std::path::Path;

use clap::Args;
use pointray_io::formats::ColumnSpec;
use pointray_io::{IoError, MemoryBudget, PointCloud, PointStream};
use pointray_scene::SceneFile;

#[derive(Args)]
pub struct ColumnsArg {
    /// What each column of a text or raw .bin points file holds, e.g. `x,y,z,intensity,ring`
    /// (names: x y z intensity r g b nx ny nz ring classification, `_` to skip; .bin columns
    /// are float32). Without it, .bin files are KITTI (x,y,z,intensity) or, named *.pcd.bin,
    /// nuScenes (x,y,z,intensity,ring). Files that name their fields (PLY, LAS, PCD, E57)
    /// refuse it.
    #[arg(long, value_name = "NAMES")]
    columns: Option<ColumnSpec>,
}

impl ColumnsArg {
    pub fn read_point_cloud(&self, path: &Path) -> Result<PointCloud, IoError> {
        pointray_io::formats::read_point_cloud_with(path, self.columns.as_ref())
    }

    /// The columns given, if any.
    pub fn columns(&self) -> Option<&ColumnSpec> {
        self.columns.as_ref()
    }

    /// The file opened for reading in chunks, or whole where `budget` allows.
    pub fn open_stream(&self, path: &Path, budget: MemoryBudget) -> Result<PointStream, IoError> {
        PointStream::open(path, self.columns.as_ref(), budget)
    }

    /// The scene with these columns for every points object that gives none of its own.
    pub fn apply_to(&self, scene: SceneFile) -> SceneFile {
        scene.with_columns(self.columns.as_ref())
    }
}
