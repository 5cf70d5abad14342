//! Stand-in point sets: a model the data lacks, replaced by as many points sampled
//! (area-uniform, seeded) on a mesh we have. Sampled once into the cache folder.

use std::path::{Path, PathBuf};

use crate::data::data_file;
use crate::error::BenchError;
use crate::suite::StandInSpec;

/// The cached points file for `spec`, sampled now when it is not cached yet.
pub fn stand_in_points(data: &Path, spec: &StandInSpec, cache: &Path) -> Result<PathBuf, BenchError> {
    let path = stand_in_path(data, spec, cache)?;
    if path.is_file() {
        return Ok(path);
    }
    let mesh = pointray_io::formats::read_triangle_mesh(&data_file(data, &spec.mesh)?)?;
    let cloud = pointray_surface::sample_mesh(&mesh, spec.count, spec.seed, false);
    pointray_io::formats::ply::write_point_cloud(&path, &cloud)?;
    Ok(path)
}

/// Where `spec`'s points file lies in `cache` (or will, once sampled). The file name carries
/// the mesh, count and seed, which fix the points exactly.
pub fn stand_in_path(data: &Path, spec: &StandInSpec, cache: &Path) -> Result<PathBuf, BenchError> {
    data_file(data, &spec.mesh)?;
    let stem = spec.mesh.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    Ok(cache.join(format!("{stem}-standin-{}-seed{}.ply", spec.count, spec.seed)))
}

/// How a stand-in is labelled in reports.
pub fn stand_in_label(spec: &StandInSpec) -> String {
    format!("stand-in: {} points sampled on {} (seed {})", spec.count, spec.mesh.display(), spec.seed)
}
