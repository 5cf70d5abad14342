//! Everything that can stop a benchmark, naming the file or case and the problem.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    #[error("{path}: cannot read the suite: {source}")]
    ReadSuite { path: PathBuf, source: std::io::Error },
    #[error("{path}: not a valid suite: {message}")]
    ParseSuite { path: PathBuf, message: String },
    #[error("{path}: model `{model}`: {problem}")]
    InvalidModel { path: PathBuf, model: String, problem: String },
    #[error("{path}: the data file is missing; set --data or POINTRAY_DATA to the data folder")]
    MissingData { path: PathBuf },
    #[error("{path}: cannot create the cache folder: {source}")]
    CacheDir { path: PathBuf, source: std::io::Error },
    #[error(
        "{path}: the cache folder lies in the git checkout {checkout}; the scale suite writes gigabytes, give --cache a folder outside it"
    )]
    CacheInRepository { path: PathBuf, checkout: PathBuf },
    #[error(transparent)]
    Io(#[from] pointray_io::IoError),
    #[error(transparent)]
    Scene(#[from] pointray_scene::SceneError),
    #[error("{case}: prep failed: {source}")]
    Prep { case: String, source: pointray_surface::PrepError },
    #[error("{case}: prep in tiles failed: {source}")]
    StreamedPrep { case: String, source: pointray_surface::tiles::stream_error::StreamError },
    #[error("{case}: {source}")]
    Store { case: String, source: pointray_patches::patch_store::StoreError },
    #[error("{case}: {source}")]
    Vulkan { case: String, source: pointray_vulkan::VulkanError },
    #[error("{case}: {source}")]
    Backend { case: String, source: pointray_render::BackendError },
    #[error("{case}: {source}")]
    Lidar { case: String, source: Box<pointray_lidar::LidarError> },
    #[error("{path}: cannot write the report: {message}")]
    WriteReport { path: PathBuf, message: String },
}
