//! The `--radius` flag, shared by the commands that prep points.

use clap::ValueEnum;
use pointray_surface::RadiusMode;

/// The support radius: the paper's (farthest of the k neighbours), adapted to the local
/// density, or just covering each point's Voronoi cell.
#[derive(Clone, Copy, ValueEnum)]
pub enum Radius {
    Paper,
    Adaptive,
    /// Just what covers each point's Voronoi cell: less overlap, fewer patches per ray.
    Cell,
}

impl From<Radius> for RadiusMode {
    fn from(radius: Radius) -> Self {
        match radius {
            Radius::Paper => RadiusMode::Paper,
            Radius::Adaptive => RadiusMode::Adaptive,
            Radius::Cell => RadiusMode::Cell,
        }
    }
}
