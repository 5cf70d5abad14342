//! The `--boxes` flag, shared by the commands that prep points.

use clap::ValueEnum;
use pointray_surface::BoxKind;

/// The box around each patch: the paper's cube of half-size d_i, or a tight box around the
/// patch over its disk.
#[derive(Clone, Copy, ValueEnum)]
pub enum Boxes {
    Cube,
    Tight,
}

impl From<Boxes> for BoxKind {
    fn from(boxes: Boxes) -> Self {
        match boxes {
            Boxes::Cube => BoxKind::Cube,
            Boxes::Tight => BoxKind::Tight,
        }
    }
}
