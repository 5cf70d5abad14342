//! The report as a markdown table: one row per view, then the pooled row.

use std::fmt;

use crate::{FidelityMetrics, FidelityReport};

const HEADER: &str = "| view | mesh px | hole % | seen hole % | pinhole % | false surface % | depth mean | depth p99 | normal mean ° | normal p95 ° | PSNR dB |\n\
                      |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|";

impl fmt::Display for FidelityReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let setup = &self.setup;
        writeln!(
            f,
            "backend {}, k = {}, acceptance {}, {} px wide, {} patches, {} triangles, {:.1} s",
            setup.backend,
            setup.k,
            setup.acceptance,
            setup.size,
            setup.patches,
            setup.triangles,
            self.seconds
        )?;
        writeln!(f)?;
        writeln!(f, "{HEADER}")?;
        for view in &self.views {
            write_row(f, &view.label, &view.metrics)?;
        }
        write_row(f, "**all**", &self.overall)
    }
}

fn write_row(f: &mut fmt::Formatter<'_>, label: &str, m: &FidelityMetrics) -> fmt::Result {
    let percent = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{:.3}", v * 100.0));
    let scientific = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{v:.2e}"));
    let fixed = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{v:.2}"));
    let psnr = m.psnr_db.map_or("inf".to_owned(), |v| format!("{v:.1}"));
    writeln!(
        f,
        "| {label} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {psnr} |",
        m.mesh_pixels,
        percent(m.hole_rate),
        percent(m.seen_hole_rate),
        percent(m.pinhole_rate),
        percent(m.false_surface_rate),
        scientific(m.depth_error_mean),
        scientific(m.depth_error_p99),
        fixed(m.normal_error_mean_degrees),
        fixed(m.normal_error_p95_degrees),
    )
}
