//! Writing a report as JSON or markdown, atomically.

use std::io::Write;
use std::path::Path;

use crate::error::BenchError;
use crate::markdown::markdown;
use crate::report::Report;

pub fn write_json(report: &Report, path: &Path) -> Result<(), BenchError> {
    let text = serde_json::to_string_pretty(report)
        .map_err(|e| BenchError::WriteReport { path: path.to_path_buf(), message: e.to_string() })?;
    write_text(&text, path)
}

pub fn write_markdown(report: &Report, path: &Path) -> Result<(), BenchError> {
    write_text(&markdown(report), path)
}

fn write_text(text: &str, path: &Path) -> Result<(), BenchError> {
    pointray_io::write_atomically(path, |writer| writer.write_all(text.as_bytes()))
        .map_err(|e| BenchError::WriteReport { path: path.to_path_buf(), message: e.to_string() })
}
