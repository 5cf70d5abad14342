//! Writing a report as JSON or markdown, atomically.

use std::io::Write;
use std::path::Path;

use serde::Serialize;

use crate::error::BenchError;

/// Any report (`Report`, `ScaleReport`) as pretty JSON.
pub fn write_json(report: &impl Serialize, path: &Path) -> Result<(), BenchError> {
    let text = serde_json::to_string_pretty(report)
        .map_err(|e| BenchError::WriteReport { path: path.to_path_buf(), message: e.to_string() })?;
    write_text(&text, path)
}

/// A report as text: its markdown (`markdown::markdown`, `scale_markdown`).
pub fn write_text(text: &str, path: &Path) -> Result<(), BenchError> {
    pointray_io::write_atomically(path, |writer| writer.write_all(text.as_bytes()))
        .map_err(|e| BenchError::WriteReport { path: path.to_path_buf(), message: e.to_string() })
}
