//! `prep_tile` and `merge_tiles`: prep cut into tile jobs, as `pointray prep --tile I --of N`
//! and `pointray prep --merge` run them, for a cluster engine to map over workers.

use std::path::PathBuf;

use pointray_io::MemoryBudget;
use pointray_io::formats::ColumnSpec;
use pointray_surface::NoProgress;
use pointray_surface::tiles::merge::{MergedTiles, merge_tile_files};
use pointray_surface::tiles::streamed_prep::prep_tile_job;
use pyo3::prelude::*;

use crate::errors::{PointrayError, to_python};
use crate::prep::PrepOptions;

/// The most tiles `pointray prep --of` accepts.
const MOST_TILES: usize = 65_536;

/// Preps tile I of the N tiles (`cut`: (I, N)) `points_path` is cut into and writes the tile file
/// `output`; returns the points the tile owns. Every job of one cut reads and sorts the
/// input the same way, so separate processes or machines agree on the cut; a folder that
/// `pointray prep --keep-sort` wrote spares each job that sort.
#[pyfunction]
#[pyo3(signature = (points_path, cut, output, options, memory=None, columns=None))]
pub fn prep_tile(
    py: Python<'_>,
    points_path: PathBuf,
    cut: (usize, usize),
    output: PathBuf,
    options: &PrepOptions,
    memory: Option<&str>,
    columns: Option<&str>,
) -> PyResult<u64> {
    check_cut(cut)?;
    let memory = memory_budget(memory)?;
    let columns = columns.map(|text| text.parse::<ColumnSpec>().map_err(|e| to_python(&e))).transpose()?;
    let settings = options.settings;
    py.detach(|| -> PyResult<u64> {
        pointray_io::ensure_outputs_spare_inputs(
            std::slice::from_ref(&points_path),
            std::slice::from_ref(&output),
        )
        .map_err(|e| to_python(&e))?;
        let places = (output.as_path(), pointray_io::folder_of(&output));
        prep_tile_job(&points_path, columns.as_ref(), &settings, cut, memory, places, &NoProgress)
            .map_err(|e| to_python(&e))
    })
}

/// Merges the tile files `tile_paths` (every tile of one cut, once each, in any order) into
/// the patch store `output`, the bytes `pointray prep --tiles N` writes in one process;
/// returns the patches written. `remove_tiles` removes each tile file once its records are
/// in, as `prep --merge --remove-tiles` does.
#[pyfunction]
#[pyo3(signature = (tile_paths, output, memory=None, remove_tiles=false))]
pub fn merge_tiles(
    py: Python<'_>,
    tile_paths: Vec<PathBuf>,
    output: PathBuf,
    memory: Option<&str>,
    remove_tiles: bool,
) -> PyResult<u64> {
    let memory = memory_budget(memory)?;
    let tiles = if remove_tiles { MergedTiles::Removed } else { MergedTiles::Kept };
    py.detach(|| -> PyResult<u64> {
        pointray_io::ensure_outputs_spare_inputs(&tile_paths, std::slice::from_ref(&output))
            .map_err(|e| to_python(&e))?;
        let merged = merge_tile_files(&tile_paths, &output, (memory, tiles), &NoProgress)
            .map_err(|e| to_python(&e))?;
        Ok(merged.patches)
    })
}

/// The cut `--tile I --of N` accepts: 1 to 65,536 tiles, and a tile among them.
fn check_cut((tile, of): (usize, usize)) -> PyResult<()> {
    if !(1..=MOST_TILES).contains(&of) {
        return Err(PointrayError::new_err(format!("of: {of} tiles; a cut has 1 to {MOST_TILES}")));
    }
    if tile >= of {
        return Err(PointrayError::new_err(format!(
            "tile {tile} is not one of {of} tiles (0 to {})",
            of - 1
        )));
    }
    Ok(())
}

/// `memory` as `--memory` reads it (`8G`, `512M`), by default half the machine's RAM.
fn memory_budget(memory: Option<&str>) -> PyResult<MemoryBudget> {
    memory.map_or_else(
        || Ok(MemoryBudget::half_of_this_machine()),
        |text| text.parse().map_err(|problem: String| PointrayError::new_err(format!("memory: {problem}"))),
    )
}
