//! The `--acceptance` flag, shared by the commands that render.

use clap::ValueEnum;
use pointray_scene::AcceptanceTest;

/// Which hits on a patch count: inside its box (the paper) or also over its disk.
#[derive(Clone, Copy, ValueEnum)]
pub enum Acceptance {
    Box,
    Disk,
}

impl From<Acceptance> for AcceptanceTest {
    fn from(acceptance: Acceptance) -> Self {
        match acceptance {
            Acceptance::Box => AcceptanceTest::Box,
            Acceptance::Disk => AcceptanceTest::Disk,
        }
    }
}
