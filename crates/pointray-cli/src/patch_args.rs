//! How the commands that measure patches make and hit them (`fidelity`, `consistency`).

use std::path::Path;

use clap::Args;
use glam::DVec3;
use pointray_io::PointCloud;
use pointray_scene::AcceptanceTest;
use pointray_surface::{PatchSet, PrepOptions, PrepParams, PrepReport, prep};

use crate::acceptance_arg::Acceptance;
use crate::boxes_arg::Boxes;
use crate::progress::PrepBar;
use crate::radius_arg::Radius;

#[derive(Args)]
pub struct PatchArgs {
    /// Neighbours for the support radius and the quadratic fit.
    #[arg(long, default_value_t = 9)]
    k: u32,
    /// Which hits on a patch count: inside its box (the paper) or also over its disk.
    #[arg(long, value_enum, default_value_t = Acceptance::Disk)]
    acceptance: Acceptance,
    /// The box around each patch.
    #[arg(long, value_enum, default_value_t = Boxes::Tight)]
    boxes: Boxes,
    /// The support radius: the point's Voronoi cell (the default), the paper's, or adapted
    /// to the local density.
    #[arg(long, value_enum, default_value_t = Radius::Cell)]
    radius: Radius,
    /// How far each patch reaches, as a fraction of the paper's support radius.
    #[arg(long, default_value_t = PrepParams::default().disk_scale)]
    disk_scale: f32,
}

impl PatchArgs {
    pub fn acceptance(&self) -> AcceptanceTest {
        self.acceptance.into()
    }

    /// Preps `cloud`, read from `path`, with normals oriented toward `sensor` when given.
    pub fn prep(
        &self,
        path: &Path,
        cloud: &PointCloud,
        sensor: Option<DVec3>,
    ) -> anyhow::Result<(PatchSet, PrepReport)> {
        let options = PrepOptions {
            params: PrepParams {
                k: self.k,
                box_kind: self.boxes.into(),
                disk_scale: self.disk_scale,
                ..PrepParams::default()
            },
            radius_mode: self.radius.into(),
            sensor,
            ..PrepOptions::default()
        };
        prep(cloud, &options, &PrepBar::default()).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
    }
}
