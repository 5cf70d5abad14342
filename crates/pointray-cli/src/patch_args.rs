//! How the commands that measure patches read, make and hit them (`fidelity`, `consistency`).

use std::path::Path;

use clap::Args;
use glam::DVec3;
use pointray_io::PointCloud;
use pointray_patches::{PatchSet, PrepSettings};
use pointray_scene::PatchAcceptance;
use pointray_surface::{PrepReport, prep};

use crate::columns_arg::ColumnsArg;
use crate::prep_settings_args::PrepSettingsArgs;
use crate::progress::PrepBar;

#[derive(Args)]
pub struct PatchArgs {
    /// Which hits on a patch count: `box` (inside its box, the paper) or `disk` (also over
    /// its support).
    #[arg(long, default_value = "disk")]
    acceptance: PatchAcceptance,
    #[command(flatten)]
    settings: PrepSettingsArgs,
    #[command(flatten)]
    columns: ColumnsArg,
}

impl PatchArgs {
    pub fn acceptance(&self) -> PatchAcceptance {
        self.acceptance
    }

    /// `--sensor`: where the scan's sensor stood, overriding the file's.
    pub fn sensor(&self) -> Option<DVec3> {
        self.settings.sensor()
    }

    /// The prep settings, checked before anything is read.
    pub fn prep_settings(&self) -> anyhow::Result<PrepSettings> {
        self.settings.settings()
    }

    pub fn read(&self, path: &Path) -> anyhow::Result<PointCloud> {
        Ok(self.columns.read_point_cloud(path)?)
    }

    /// Preps `cloud`, read from `path`.
    pub fn prep(
        &self,
        path: &Path,
        cloud: &PointCloud,
        settings: &PrepSettings,
    ) -> anyhow::Result<(PatchSet, PrepReport)> {
        prep(cloud, settings, &PrepBar::default()).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
    }
}
