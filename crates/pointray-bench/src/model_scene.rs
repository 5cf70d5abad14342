//! A suite model's scene, with its point set (exact or stand-in) or its triangle mesh as the
//! model object, loaded through the scene crate (point sets are prepped once, then cached).

use std::path::{Path, PathBuf};

use pointray_scene::SceneFile;
use pointray_scene::load::{LoadOptions, LoadedScene, load_scene_file};

use crate::data::data_file;
use crate::error::BenchError;
use crate::stand_in::stand_in_points;
use crate::suite::ModelSpec;

/// What stands for the model in its scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelGeometry {
    Points,
    Mesh,
}

/// The points file for the model: the exact file, or its cached stand-in.
pub fn model_points(model: &ModelSpec, data: &Path, cache: &Path) -> Result<PathBuf, BenchError> {
    match (&model.points, &model.stand_in) {
        (Some(points), _) => data_file(data, points),
        (None, Some(stand_in)) => stand_in_points(data, stand_in, cache),
        (None, None) => Err(BenchError::InvalidModel {
            path: cache.to_path_buf(),
            model: model.name.clone(),
            problem: "it has neither points nor a stand-in".into(),
        }),
    }
}

/// The model's scene with `geometry` as the model; `None` for a mesh when it has none.
pub fn load_model_scene(
    model: &ModelSpec,
    geometry: ModelGeometry,
    data: &Path,
    cache: &Path,
) -> Result<Option<LoadedScene>, BenchError> {
    let (kind, path) = match geometry {
        ModelGeometry::Points => ("points", model_points(model, data, cache)?),
        ModelGeometry::Mesh => match &model.mesh {
            Some(mesh) => ("mesh", data_file(data, mesh)?),
            None => return Ok(None),
        },
    };
    let scene_path = cache.join(format!("{}-{kind}.toml", model.name));
    load_with_model(&model.name, &model.scene, kind, &path, &scene_path, cache).map(Some)
}

/// Loads the scene `table` with `path` (of `kind`, "points" or "mesh") as its first object,
/// the model `name`; `scene_path` stands for the scene file in messages. Points files are
/// prepped through `cache`.
pub fn load_with_model(
    name: &str,
    table: &toml::Table,
    kind: &str,
    path: &Path,
    scene_path: &Path,
    cache: &Path,
) -> Result<LoadedScene, BenchError> {
    let mut table = table.clone();
    let path_text = std::path::absolute(path).unwrap_or(path.to_path_buf()).to_string_lossy().into_owned();
    if let Some(object) = table
        .get_mut("objects")
        .and_then(|o| o.as_array_mut())
        .and_then(|o| o.first_mut())
        .and_then(|o| o.as_table_mut())
    {
        object.insert("type".into(), kind.into());
        object.insert("path".into(), path_text.into());
    }
    let text = toml::to_string(&table).map_err(|e| BenchError::InvalidModel {
        path: scene_path.to_path_buf(),
        model: name.to_string(),
        problem: e.to_string(),
    })?;
    let file = SceneFile::parse(&text, scene_path)?;
    let options = LoadOptions { cache_dir: Some(cache), ..LoadOptions::default() };
    Ok(load_scene_file(&file, &options)?)
}
