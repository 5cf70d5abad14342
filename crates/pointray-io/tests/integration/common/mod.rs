//! Fixture files the reader tests write.

use std::path::PathBuf;

/// Writes `bytes` to `name` in a fresh temporary directory (kept alive by the returned guard).
pub fn fixture(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).expect("write fixture");
    (dir, path)
}
