//! Errors that name the file and what is wrong with it.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum IoError {
    #[error("{path}: {source}")]
    Os { path: PathBuf, source: std::io::Error },
    #[error("{path}: {problem}")]
    Malformed { path: PathBuf, problem: String },
    #[error("{path}: unsupported {what}; supported: {supported}")]
    Unsupported { path: PathBuf, what: String, supported: String },
}

impl IoError {
    pub fn malformed(path: impl Into<PathBuf>, problem: impl Into<String>) -> Self {
        Self::Malformed { path: path.into(), problem: problem.into() }
    }

    pub fn os(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Os { path: path.into(), source }
    }
}
