//! Why a scan could not be made. Every message names the setting or file at fault.

use pointray_io::IoError;
use pointray_scene::SceneError;

#[derive(Debug, thiserror::Error)]
pub enum LidarError {
    /// A sensor or pose setting out of its range; `setting` is the command-line flag's name.
    #[error("invalid --{setting}: {problem}")]
    InvalidSetting { setting: &'static str, problem: String },
    #[error(
        "the scan would cast {rays} rays, more than the {limit} one scan may cast; \
         use a coarser --azimuth-step or fewer stations"
    )]
    TooManyRays { rays: u64, limit: u64 },
    #[error("surface `{name}`: {problem}")]
    BadSurface { name: String, problem: String },
    #[error("the scene has no surface to scan")]
    EmptyScene,
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Io(#[from] IoError),
    /// The caster casting into a map (a GPU's) failed.
    #[error("casting rays into the map failed: {0}")]
    Cast(#[source] Box<dyn std::error::Error + Send + Sync>),
}

impl LidarError {
    pub(crate) fn invalid(setting: &'static str, problem: impl Into<String>) -> Self {
        Self::InvalidSetting { setting, problem: problem.into() }
    }
}
