//! Why prep in bounded memory (`tiles::streamed_prep`) or a merge of tile files stopped; every
//! message names the file concerned.

use std::path::PathBuf;

use pointray_io::IoError;
use pointray_patches::patch_store::StoreError;

use crate::prep_error::PrepError;

#[derive(Debug, thiserror::Error)]
pub enum StreamError {
    #[error(transparent)]
    Io(#[from] IoError),
    #[error(transparent)]
    Store(#[from] StoreError),
    #[error("{path}: {source}")]
    Prep { path: PathBuf, source: PrepError },
    /// The memory budget cannot hold what the work needs.
    #[error("{path}: {problem}")]
    OverBudget { path: PathBuf, problem: String },
    /// A tile file or a kept sort that is not one, or tile files that do not make one store.
    #[error("{path}: {problem}")]
    BadTile { path: PathBuf, problem: String },
}

impl StreamError {
    pub(crate) fn scratch(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io(IoError::os(path, source))
    }
}
