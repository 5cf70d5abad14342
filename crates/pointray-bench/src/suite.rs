//! A benchmark suite file (`bench/suites/*.toml`): models, where their points come from, the
//! mesh for the limit, the sizes to time, the paper's FPS and the scene each sits in.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::error::BenchError;

/// The `table1` suite, built in so that `pointray bench table1` runs from anywhere.
pub const TABLE1: &str = include_str!("../../../bench/suites/table1.toml");

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Suite {
    pub name: String,
    pub models: Vec<ModelSpec>,
    /// Where the suite was read from (for messages).
    #[serde(skip)]
    pub path: PathBuf,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    pub name: String,
    /// An exact points file, relative to the data folder.
    pub points: Option<PathBuf>,
    /// Or a stand-in sampled on a mesh.
    pub stand_in: Option<StandInSpec>,
    /// The triangle mesh for the limit, relative to the data folder.
    pub mesh: Option<PathBuf>,
    /// Sizes as "WIDTHxHEIGHT".
    pub sizes: Vec<String>,
    /// The paper's FPS by size.
    #[serde(default)]
    pub paper_fps: BTreeMap<String, f64>,
    /// A scene file's tables; its first object is the model, whose `type` and `path` the
    /// benchmark fills in.
    pub scene: toml::Table,
}

#[derive(Clone, Debug, Deserialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct StandInSpec {
    pub mesh: PathBuf,
    pub count: usize,
    pub seed: u64,
}

impl Suite {
    pub fn read(path: &Path) -> Result<Self, BenchError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| BenchError::ReadSuite { path: path.to_path_buf(), source })?;
        Self::parse(&text, path)
    }

    pub fn table1() -> Result<Self, BenchError> {
        Self::parse(TABLE1, Path::new("bench/suites/table1.toml"))
    }

    /// Parses and checks a suite; `path` names it in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Self, BenchError> {
        let mut suite: Suite = toml::from_str(text)
            .map_err(|e| BenchError::ParseSuite { path: path.to_path_buf(), message: e.to_string() })?;
        suite.path = path.to_path_buf();
        for model in &suite.models {
            model.check().map_err(|problem| BenchError::InvalidModel {
                path: path.to_path_buf(),
                model: model.name.clone(),
                problem,
            })?;
        }
        Ok(suite)
    }
}

impl ModelSpec {
    fn check(&self) -> Result<(), String> {
        if self.points.is_some() == self.stand_in.is_some() {
            return Err("give exactly one of `points` and `stand_in`".into());
        }
        if self.stand_in.as_ref().is_some_and(|s| s.count == 0) {
            return Err("a stand-in needs at least one point".into());
        }
        for size in self.sizes.iter().chain(self.paper_fps.keys()) {
            parse_size(size)?;
        }
        let has_object = self.scene.get("objects").and_then(|o| o.as_array()).is_some_and(|o| !o.is_empty());
        if !has_object {
            return Err("its scene needs at least one object, the model".into());
        }
        Ok(())
    }

    /// The sizes to time as (width, height).
    /// The data files this model reads, inside the data folder `data`.
    pub fn input_files(&self, data: &Path) -> Vec<PathBuf> {
        let stand_in_mesh = self.stand_in.as_ref().map(|stand_in| &stand_in.mesh);
        [self.points.as_ref(), self.mesh.as_ref(), stand_in_mesh]
            .into_iter()
            .flatten()
            .map(|p| data.join(p))
            .collect()
    }

    pub fn size_list(&self) -> Vec<(u32, u32)> {
        self.sizes.iter().filter_map(|s| parse_size(s).ok()).collect()
    }

    pub fn paper_fps_at(&self, width: u32, height: u32) -> Option<f64> {
        self.paper_fps.get(&format!("{width}x{height}")).copied()
    }
}

/// "640x480" as (640, 480).
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("size `{text}` is not WIDTHxHEIGHT with both at least 1");
    let (w, h) = text.split_once('x').ok_or_else(bad)?;
    let (w, h): (u32, u32) = (w.parse().map_err(|_| bad())?, h.parse().map_err(|_| bad())?);
    if w == 0 || h == 0 {
        return Err(bad());
    }
    Ok((w, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table1_has_the_papers_six_models() {
        let suite = Suite::table1().expect("the built-in suite parses");
        let names: Vec<&str> = suite.models.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["Bunny", "Horse", "Armadillo", "Dragon", "Buddha", "1,195K model"]);
        let counts: Vec<usize> =
            suite.models.iter().filter_map(|m| m.stand_in.as_ref().map(|s| s.count)).collect();
        assert_eq!(counts, [172_974, 437_645, 543_652, 1_195_000]);
        assert_eq!(suite.models[0].paper_fps_at(1858, 1057), Some(676.0));
        assert_eq!(suite.models[5].size_list(), [(600, 400)]);
    }

    #[test]
    fn bad_models_are_errors_naming_the_model() {
        let text =
            "name = \"s\"\n[[models]]\nname = \"m\"\nsizes = [\"64x0\"]\n[models.scene]\nobjects = [{}]\n";
        let error = Suite::parse(text, Path::new("s.toml")).expect_err("neither points nor stand-in");
        assert!(error.to_string().contains("s.toml: model `m`"), "{error}");
        let text = text.replace("name = \"m\"", "name = \"m\"\npoints = \"p.ply\"");
        let error = Suite::parse(&text, Path::new("s.toml")).expect_err("zero height");
        assert!(error.to_string().contains("64x0"), "{error}");
    }
}
