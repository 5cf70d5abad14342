//! A whole benchmark run: the device, the settings, every case, and the limit rows derived
//! from the point-set and mesh cases.

use serde::Serialize;

use crate::case_result::{CaseResult, Variant};

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    pub suite: String,
    pub device: String,
    pub driver: String,
    pub vulkan_api: String,
    pub warmup_frames: u32,
    pub timed_frames: u32,
    pub cases: Vec<CaseResult>,
    pub limits: Vec<LimitRow>,
}

/// A point set's frame time over its own mesh's, in the same scene and size.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LimitRow {
    pub model: String,
    pub width: u32,
    pub height: u32,
    pub points_frame_ms: f64,
    pub mesh_frame_ms: f64,
    pub points_over_mesh: f64,
}

/// Pairs every point-set case with the mesh case of the same model and size.
pub fn limit_rows(cases: &[CaseResult]) -> Vec<LimitRow> {
    let of = |variant| cases.iter().filter(move |c: &&CaseResult| c.variant == variant);
    of(Variant::Points)
        .filter_map(|points| {
            let mesh = of(Variant::Mesh)
                .find(|m| m.model == points.model && (m.width, m.height) == (points.width, points.height))?;
            Some(LimitRow {
                model: points.model.clone(),
                width: points.width,
                height: points.height,
                points_frame_ms: points.frame_median_ms,
                mesh_frame_ms: mesh.frame_median_ms,
                points_over_mesh: points.frame_median_ms / mesh.frame_median_ms,
            })
        })
        .collect()
}
