//! Errors from reading scene files, loading what they name and writing images. Every message
//! names the file it is about.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{path}: cannot read the scene file: {source}")]
    Read { path: PathBuf, source: std::io::Error },
    /// TOML syntax errors, unknown keys and values of the wrong type; `message` says where.
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    /// A value of the right type that makes no sense, e.g. a negative radius.
    #[error("{path}: {key}: {problem}")]
    Invalid { path: PathBuf, key: String, problem: String },
    #[error("{scene}: {key}: {source}")]
    Input { scene: PathBuf, key: String, source: pointray_io::IoError },
    #[cfg(feature = "load")]
    #[error("{scene}: {key}: preparing patches from {file} failed: {source}")]
    Prep { scene: PathBuf, key: String, file: PathBuf, source: pointray_surface::PrepError },
    #[error("{scene}: {key}: {source}")]
    PatchStore { scene: PathBuf, key: String, source: pointray_patches::patch_store::StoreError },
    #[error("{path}: cannot create the patch cache folder: {source}")]
    CacheDir { path: PathBuf, source: std::io::Error },
    #[error("{path}: cannot write the image: {source}")]
    ImageOutput { path: PathBuf, source: pointray_io::IoError },
    #[error("{path}: {problem}")]
    ImageFormat { path: PathBuf, problem: String },
}

/// A value that parsed but makes no sense, found before the scene file's path is known to the
/// check; `SceneError::Invalid` adds the path.
#[cfg(feature = "load")]
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct InvalidValue {
    pub key: String,
    pub problem: String,
}

#[cfg(feature = "load")]
impl InvalidValue {
    pub fn new(key: impl Into<String>, problem: impl Into<String>) -> Self {
        Self { key: key.into(), problem: problem.into() }
    }

    /// Places the key under `parent`, e.g. `scale` under `objects[2].transform`.
    pub fn within(self, parent: &str) -> Self {
        Self { key: format!("{parent}.{}", self.key), problem: self.problem }
    }

    pub fn in_file(self, path: impl Into<PathBuf>) -> SceneError {
        SceneError::Invalid { path: path.into(), key: self.key, problem: self.problem }
    }
}
