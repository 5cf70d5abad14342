//! The report as markdown: Table 1 beside the paper, the limit, the ablations, the costs.

use std::fmt::Write;

use crate::case_result::{CaseResult, Variant};
use crate::measure::MIN_WARMUP;
use crate::report::Report;

const MIB: f64 = 1024.0 * 1024.0;

pub fn markdown(report: &Report) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "## {} on {}\n", report.suite, report.device);
    let _ = writeln!(
        out,
        "Driver {}, Vulkan {}; warm-up in rounds of {} frames for at least {} s, then {} timed frames per \
         case. FPS = 1 / median GPU \
         time of a whole frame (trace, then the copy of its sRGB8 display colour to host memory; \
         timestamps); rays counted on the GPU (primary, shadow and reflection), and the patch \
         intersection shader's calls by those rays, per ray.\n",
        report.driver,
        report.vulkan_api,
        report.warmup_frames,
        MIN_WARMUP.as_secs_f32(),
        report.timed_frames
    );
    frames_table(&mut out, report);
    limit_table(&mut out, report);
    ablation_table(&mut out, report);
    costs_table(&mut out, report);
    stand_in_notes(&mut out, report);
    out
}

fn model_name(case: &CaseResult) -> String {
    match case.stand_in {
        Some(_) => format!("{} (stand-in)", case.model),
        None => case.model.clone(),
    }
}

fn optional(value: Option<f64>, digits: usize) -> String {
    value.map(|v| format!("{v:.digits$}")).unwrap_or_else(|| "–".into())
}

fn frames_table(out: &mut String, report: &Report) {
    let _ = writeln!(
        out,
        "| model | points | size | paper FPS | our FPS | ours / paper | frame ms (median / p90) | \
         trace ms (median / p90) | rays / frame | intersection calls / ray | G rays/s |\n\
         |---|---|---|---|---|---|---|---|---|---|---|"
    );
    for case in report.cases.iter().filter(|c| c.variant == Variant::Points) {
        let _ = writeln!(
            out,
            "| {} | {} | {}x{} | {} | {:.0} | {} | {:.3} / {:.3} | {:.3} / {:.3} | {} | {:.2} | {:.2} |",
            model_name(case),
            case.primitives,
            case.width,
            case.height,
            optional(case.paper_fps, 0),
            case.fps,
            optional(case.ratio_to_paper, 1),
            case.frame_median_ms,
            case.frame_p90_ms,
            case.trace_median_ms,
            case.trace_p90_ms,
            case.rays_per_frame,
            case.intersection_calls_per_ray,
            case.rays_per_second / 1e9
        );
    }
    out.push('\n');
}

fn limit_table(out: &mut String, report: &Report) {
    if report.limits.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "### The limit: the model's own triangle mesh in the same scene\n\n\
         | model | size | points frame ms | mesh frame ms | points / mesh |\n|---|---|---|---|---|"
    );
    for row in &report.limits {
        let _ = writeln!(
            out,
            "| {} | {}x{} | {:.3} | {:.3} | {:.2} |",
            row.model, row.width, row.height, row.points_frame_ms, row.mesh_frame_ms, row.points_over_mesh
        );
    }
    out.push('\n');
}

fn ablation_table(out: &mut String, report: &Report) {
    let is_ablation = |c: &&CaseResult| !matches!(c.variant, Variant::Points | Variant::Mesh);
    let ablations: Vec<&CaseResult> = report.cases.iter().filter(is_ablation).collect();
    if ablations.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "### Ablations (frame time against the default: one geometry, split buffers, tight boxes, disk test, \
         display output)\n\n\
         | model | size | variant | frame ms | variant / default |\n|---|---|---|---|---|"
    );
    for case in ablations {
        let default = report.cases.iter().find(|c| {
            c.variant == Variant::Points
                && c.model == case.model
                && (c.width, c.height) == (case.width, case.height)
        });
        let ratio = default.map(|d| case.frame_median_ms / d.frame_median_ms);
        let _ = writeln!(
            out,
            "| {} | {}x{} | {} | {:.3} | {} |",
            model_name(case),
            case.width,
            case.height,
            case.variant.label(),
            case.frame_median_ms,
            optional(ratio, 2)
        );
    }
    out.push('\n');
}

fn costs_table(out: &mut String, report: &Report) {
    let _ = writeln!(
        out,
        "### Costs (wall time of each build, compaction included; GPU memory)\n\n\
         | model | variant | primitives | BLAS build ms | TLAS build ms | BLAS MiB | TLAS MiB | buffers MiB |\n\
         |---|---|---|---|---|---|---|---|"
    );
    let mut seen = Vec::new();
    for case in &report.cases {
        let key = (case.model.as_str(), case.variant);
        if seen.contains(&key) {
            continue;
        }
        seen.push(key);
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.1} | {:.2} | {:.2} | {:.3} | {:.2} |",
            model_name(case),
            case.variant.label(),
            case.primitives,
            case.blas_build_ms,
            case.tlas_build_ms,
            case.blas_bytes as f64 / MIB,
            case.tlas_bytes as f64 / MIB,
            case.geometry_bytes as f64 / MIB
        );
    }
    out.push('\n');
}

fn stand_in_notes(out: &mut String, report: &Report) {
    let mut seen: Vec<&str> = Vec::new();
    for case in &report.cases {
        if let Some(label) = &case.stand_in
            && !seen.contains(&case.model.as_str())
        {
            seen.push(&case.model);
            let _ = writeln!(out, "- {}: {label}", case.model);
        }
    }
}
