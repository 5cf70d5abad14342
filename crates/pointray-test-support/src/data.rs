//! The checkout's `data/` folder: the scanned models and the LiDAR tile every test may read
//! (data/SOURCES.md). It is part of the checkout, so a test never skips for want of it.

use std::path::{Path, PathBuf};

/// The checkout's `data/` folder.
pub fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data")
}

/// `relative` inside `data/`; a test that names a file not there fails, naming it.
pub fn data_file(relative: &str) -> PathBuf {
    let path = data_dir().join(relative);
    assert!(path.is_file(), "{} is not in the checkout's data folder", path.display());
    path
}
