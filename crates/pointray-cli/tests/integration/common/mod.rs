//! What the CLI tests share.

use std::path::{Path, PathBuf};

/// A file under the shared test data (`../shared/data` from the workspace root, or
/// `$POINTRAY_DATA`); `None` (with a note) when it is missing, a failure instead when
/// `CI=true`, where the data must be present.
pub fn data_file(relative: &str) -> Option<PathBuf> {
    let root = std::env::var_os("POINTRAY_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"));
    let path = root.join(relative);
    if path.is_file() {
        return Some(path);
    }
    assert!(std::env::var("CI").as_deref() != Ok("true"), "test data {} is missing", path.display());
    eprintln!("note: skipping, test data {} is missing", path.display());
    None
}
