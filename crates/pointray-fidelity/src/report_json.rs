//! The report as JSON. `serde_json` is a dependency for this alone: issue 4 asks for the
//! fidelity numbers as JSON as well as a table, and a hand-written encoder would have to get
//! escaping and non-finite numbers right by itself.

use std::io::Write;
use std::path::Path;

use crate::{FidelityError, FidelityReport};

impl FidelityReport {
    /// Writes the report as pretty-printed JSON, atomically.
    pub fn write_json(&self, path: &Path) -> Result<(), FidelityError> {
        pointray_io::write_atomically(path, |writer| {
            serde_json::to_writer_pretty(&mut *writer, self)?;
            writeln!(writer)
        })
        .map_err(|source| FidelityError::Write { path: path.to_owned(), source })
    }
}
