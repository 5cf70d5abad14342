//! Reports as JSON. `serde_json` is a dependency for this alone: the fidelity numbers are
//! wanted as JSON as well as a table, and a hand-written encoder would have to get escaping
//! and non-finite numbers right by itself.

use std::io::Write;
use std::path::Path;

use serde::Serialize;

use crate::{FidelityError, FidelityReport};

impl FidelityReport {
    /// Writes the report as pretty-printed JSON, atomically.
    pub fn write_json(&self, path: &Path) -> Result<(), FidelityError> {
        write_json(self, path)
    }
}

/// Writes `report` as pretty-printed JSON, atomically.
pub(crate) fn write_json(report: &impl Serialize, path: &Path) -> Result<(), FidelityError> {
    pointray_io::write_atomically(path, |writer| {
        serde_json::to_writer_pretty(&mut *writer, report)?;
        writeln!(writer)
    })
    .map_err(|source| FidelityError::Write { path: path.to_owned(), source })
}
