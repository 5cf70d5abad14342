//! How the commands that measure patches read, make and hit them (`fidelity`, `consistency`).

use std::path::Path;

use clap::Args;
use glam::DVec3;
use pointray_io::PointCloud;
use pointray_scene::PatchAcceptance;
use pointray_surface::input_validation::validate_options;
use pointray_surface::{PatchSet, PrepOptions, PrepParams, PrepReport, prep};

use crate::boxes_arg::Boxes;
use crate::columns_arg::ColumnsArg;
use crate::progress::PrepBar;
use crate::radius_arg::Radius;
use crate::scan_arg::Scan;

#[derive(Args)]
pub struct PatchArgs {
    /// Neighbours for the support radius and the quadratic fit.
    #[arg(long, default_value_t = 9)]
    k: u32,
    /// Which hits on a patch count: `box` (inside its box, the paper) or `disk` (also over
    /// its support).
    #[arg(long, default_value = "disk")]
    acceptance: PatchAcceptance,
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
    /// LiDAR scans: `auto` shapes patches along the scan lines when the sensor is known;
    /// `off` treats the cloud as unstructured points.
    #[arg(long, value_enum, default_value_t = Scan::Auto)]
    scan: Scan,
    #[command(flatten)]
    columns: ColumnsArg,
}

impl PatchArgs {
    pub fn acceptance(&self) -> PatchAcceptance {
        self.acceptance
    }

    /// The prep settings, with normals oriented toward `sensor` when given; checked before
    /// anything is read.
    pub fn prep_options(&self, sensor: Option<DVec3>) -> anyhow::Result<PrepOptions> {
        let options = PrepOptions {
            params: PrepParams {
                k: self.k,
                box_kind: self.boxes.into(),
                disk_scale: self.disk_scale,
                ..PrepParams::default()
            },
            radius_mode: self.radius.into(),
            sensor,
            scan: self.scan.into(),
            ..PrepOptions::default()
        };
        validate_options(&options).map_err(crate::commands::prep::flag_error)?;
        Ok(options)
    }

    pub fn read(&self, path: &Path) -> anyhow::Result<PointCloud> {
        Ok(self.columns.read_point_cloud(path)?)
    }

    /// Preps `cloud`, read from `path`.
    pub fn prep(
        &self,
        path: &Path,
        cloud: &PointCloud,
        options: &PrepOptions,
    ) -> anyhow::Result<(PatchSet, PrepReport)> {
        prep(cloud, options, &PrepBar::default()).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
    }
}
