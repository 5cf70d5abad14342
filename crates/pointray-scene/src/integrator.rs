//! Which light transport a render computes.

use serde::Deserialize;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Integrator {
    /// The paper's: Phong at each hit, hard shadows from point and directional lights,
    /// mirror reflections weighted by `reflectivity` (the rendering contract).
    #[default]
    Whitted,
    /// Unidirectional path tracing with next-event estimation and multiple importance
    /// sampling over the materials' BSDFs, the lights and the sky (the background).
    Path,
}

/// The names a scene file and `--integrator` accept.
pub const INTEGRATOR_NAMES: [&str; 2] = ["whitted", "path"];

impl std::str::FromStr for Integrator {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text.trim() {
            "whitted" => Ok(Self::Whitted),
            "path" => Ok(Self::Path),
            _ => Err(format!("unknown integrator `{text}`; the integrators are {INTEGRATOR_NAMES:?}")),
        }
    }
}
