//! Errors that name the file and what is wrong with it.

use std::path::PathBuf;

/// Every failure names the file it concerns.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    #[error("{path}: {source}")]
    Os { path: PathBuf, source: std::io::Error },
    #[error("{path}: {problem}")]
    Malformed { path: PathBuf, problem: String },
    #[error("{path}: unsupported {what}; supported: {supported}")]
    Unsupported { path: PathBuf, what: String, supported: String },
    #[error("{output}: refusing to write over the input file {input}")]
    SameFile { input: PathBuf, output: PathBuf },
    /// A path that cannot serve: a folder or device where a file is wanted, a missing folder.
    #[error("{path}: {problem}")]
    Unusable { path: PathBuf, problem: String },
    /// Data handed to a writer that cannot be written (mismatched lengths, bad indices, ...).
    #[error("{path}: cannot write: {problem}")]
    Unwritable { path: PathBuf, problem: String },
}

impl IoError {
    pub fn malformed(path: impl Into<PathBuf>, problem: impl Into<String>) -> Self {
        Self::Malformed { path: path.into(), problem: problem.into() }
    }

    pub fn unwritable(path: impl Into<PathBuf>, problem: impl Into<String>) -> Self {
        Self::Unwritable { path: path.into(), problem: problem.into() }
    }

    pub fn unusable(path: impl Into<PathBuf>, problem: impl Into<String>) -> Self {
        Self::Unusable { path: path.into(), problem: problem.into() }
    }

    pub fn os(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Os { path: path.into(), source }
    }
}
