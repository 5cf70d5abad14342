//! The `--acceptance` flag, shared by the commands that render.

use clap::ValueEnum;
use pointray_scene::PatchAcceptance;

/// Which hits on a patch count: inside its box (the paper) or also over its disk.
#[derive(Clone, Copy, ValueEnum)]
pub enum Acceptance {
    Box,
    Disk,
}

impl From<Acceptance> for PatchAcceptance {
    fn from(acceptance: Acceptance) -> Self {
        match acceptance {
            Acceptance::Box => PatchAcceptance::Box,
            Acceptance::Disk => PatchAcceptance::Disk,
        }
    }
}
