//! The `fidelity` flags that choose the cameras.

use clap::Args;
use glam::Vec3;
use pointray_fidelity::ViewSpec;
use pointray_fidelity::measure::DEFAULT_FOV_DEGREES;

use crate::point_arg::parse_finite;

#[derive(Args)]
pub struct ViewArgs {
    /// Cameras: a number (6 or more around the mesh: 6 look along the axes, more are spread
    /// evenly), `sensor[:YAWS]` (at the scan's sensor, YAWS views around the horizon, 4 by
    /// default, each as tall as the elevations the returns span) or `above[:HEIGHT]` (straight
    /// down from HEIGHT, 20 by default, above the points' centre). Repeat or separate with
    /// commas; 6 when no view is given.
    #[arg(long, value_delimiter = ',', value_parser = parse_view)]
    views: Vec<ViewSpec>,
    /// A camera position `x,y,z`, paired in order with `--view-at`; repeat, or separate
    /// several with `;`.
    #[arg(long, value_parser = parse_points, allow_hyphen_values = true)]
    view_from: Vec<Points>,
    /// Where each `--view-from` camera looks, `x,y,z`.
    #[arg(long, value_parser = parse_points, allow_hyphen_values = true)]
    view_at: Vec<Points>,
    /// The scan's up axis: `above` looks down it, sensor views are level with it, explicit
    /// views keep it up.
    #[arg(long, default_value = "0,0,1", value_parser = parse_vector, allow_hyphen_values = true)]
    pub up: Vec3,
    /// The vertical field of view, in degrees, of explicit and `above` views.
    #[arg(long, default_value_t = DEFAULT_FOV_DEGREES, allow_hyphen_values = true)]
    pub fov: f32,
}

/// One `--view-from` or `--view-at` value.
#[derive(Clone)]
struct Points(Vec<Vec3>);

impl ViewArgs {
    /// The views asked for, in order: `--views`, then the explicit cameras.
    pub fn specs(&self) -> anyhow::Result<Vec<ViewSpec>> {
        let from: Vec<Vec3> = self.view_from.iter().flat_map(|points| points.0.clone()).collect();
        let at: Vec<Vec3> = self.view_at.iter().flat_map(|points| points.0.clone()).collect();
        if from.len() != at.len() {
            anyhow::bail!(
                "--view-from gives {} camera positions but --view-at {} targets",
                from.len(),
                at.len()
            );
        }
        let explicit: Vec<ViewSpec> =
            from.into_iter().zip(at).map(|(from, at)| ViewSpec::Explicit { from, at }).collect();
        let mut specs = self.views.clone();
        if specs.is_empty() && explicit.is_empty() {
            specs.push(ViewSpec::Around { count: 6 });
        }
        specs.extend(explicit);
        for spec in &specs {
            spec.validate()?;
        }
        Ok(specs)
    }

    pub fn wants_sensor(&self) -> bool {
        self.views.iter().any(|spec| matches!(spec, ViewSpec::Sensor { .. }))
    }
}

fn parse_view(text: &str) -> Result<ViewSpec, String> {
    text.parse().map_err(|e: pointray_fidelity::FidelityError| e.to_string())
}

/// `x,y,z`, or several separated by `;`, all finite.
fn parse_points(text: &str) -> Result<Points, String> {
    text.split(';')
        .map(|point| parse_finite(point).map(|p| p.as_vec3()))
        .collect::<Result<_, _>>()
        .map(Points)
}

fn parse_vector(text: &str) -> Result<Vec3, String> {
    parse_finite(text).map(|p| p.as_vec3())
}
