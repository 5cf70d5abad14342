//! The procedural demo scene: points sampled analytically on a torus and a sphere, on a
//! reflective ground, lit by one light. It needs no data file: the scene file is compiled in
//! (it is `scenes/demo.toml`, kept in one place so the example and the demo cannot drift).

use std::path::Path;

use crate::error::SceneError;
use crate::load::{LoadOptions, LoadedScene, load_scene_file};
use crate::{Scene, SceneFile};

/// The text of `scenes/demo.toml`.
pub const DEMO_SCENE_TOML: &str = include_str!("../../../scenes/demo.toml");

/// The demo with its render settings (640x480, one sample, depth 2). Nothing is written: the
/// points are prepped in memory.
pub fn load_demo(options: &LoadOptions) -> Result<LoadedScene, SceneError> {
    let file = SceneFile::parse(DEMO_SCENE_TOML, Path::new("scenes/demo.toml"))?;
    load_scene_file(&file, options)
}

pub fn demo_scene() -> Result<Scene, SceneError> {
    Ok(load_demo(&LoadOptions::default())?.scene)
}
