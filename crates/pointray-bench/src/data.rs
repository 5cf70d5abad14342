//! Where the suite's data files and its cache live.

use std::path::{Path, PathBuf};

use crate::error::BenchError;

/// `relative` inside the data folder; an error naming the file when it is missing.
pub fn data_file(data: &Path, relative: &Path) -> Result<PathBuf, BenchError> {
    let path = data.join(relative);
    if path.is_file() { Ok(path) } else { Err(BenchError::MissingData { path }) }
}

pub fn ensure_cache_dir(cache: &Path) -> Result<(), BenchError> {
    std::fs::create_dir_all(cache)
        .map_err(|source| BenchError::CacheDir { path: cache.to_path_buf(), source })
}
