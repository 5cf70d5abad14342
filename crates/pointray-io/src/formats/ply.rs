//! PLY (Stanford polygon format): ascii, binary little and big endian, read and written with
//! the `ply-rs-bw` crate. Point clouds take x, y, z (any numeric type), and optionally nx, ny,
//! nz, red, green, blue (integers scaled by their type's maximum, or floats in [0, 1]),
//! intensity or scalar_intensity, ring and classification (any integer type), and the
//! per-point sensor position sensor_x, sensor_y, sensor_z. Other properties (a scanner's
//! azimuth or time, say) are skipped. Meshes take faces as `vertex_indices` or `vertex_index`
//! lists of any integer type, fan-triangulated.

pub(crate) mod chunks;
mod face;
mod reader;
mod vertex;
mod writer;

use std::path::Path;

pub use ply_rs_bw::ply::Encoding as PlyEncoding;
pub use reader::has_magic;

use crate::{IoError, PointCloud, TriangleMesh};

/// Reads the vertices of a PLY file (faces, if any, are ignored) as a point cloud.
pub fn read_point_cloud(path: &Path) -> Result<PointCloud, IoError> {
    if let Some(chunked) = chunks::PlyChunks::open(path)?
        && let Some(cloud) = chunked.read_whole()?
    {
        return Ok(cloud);
    }
    let contents = reader::read_contents(path, false)?;
    vertex::into_point_cloud(&contents.vertices, &contents.layout).map_err(|p| IoError::malformed(path, p))
}

/// Reads a PLY mesh: its vertices and its faces, fan-triangulated.
pub fn read_triangle_mesh(path: &Path) -> Result<TriangleMesh, IoError> {
    let malformed = |problem| IoError::malformed(path, problem);
    let contents = reader::read_contents(path, true)?;
    let faces = contents.faces.ok_or_else(|| malformed("no 'face' element: not a mesh".to_string()))?;
    let positions = vertex::positions(&contents.vertices).map_err(malformed)?;
    let mut mesh =
        TriangleMesh { positions: positions.iter().map(|p| p.as_vec3()).collect(), triangles: Vec::new() };
    face::append_faces(&faces, &mut mesh).map_err(malformed)?;
    Ok(mesh)
}

/// Writes a cloud as binary little-endian PLY, atomically. Positions are float, or double when
/// any coordinate exceeds 1e5 in magnitude; then, when present, normals (float `nx ny nz`),
/// colours (uchar `red green blue`), intensities (float), rings (ushort `ring`),
/// classifications (uchar `classification`) and sensor origins (double `sensor_x sensor_y
/// sensor_z`), so that reading the file back gives the same cloud.
pub fn write_point_cloud(path: &Path, cloud: &PointCloud) -> Result<(), IoError> {
    write_point_cloud_as(path, cloud, PlyEncoding::BinaryLittleEndian)
}

/// [`write_point_cloud`] in a chosen encoding (ascii is handy for inspection and tests).
pub fn write_point_cloud_as(path: &Path, cloud: &PointCloud, encoding: PlyEncoding) -> Result<(), IoError> {
    writer::write_cloud(path, cloud, encoding)
}

/// Writes a mesh as binary little-endian PLY (float positions, `list uchar uint
/// vertex_indices`), atomically.
pub fn write_triangle_mesh(path: &Path, mesh: &TriangleMesh) -> Result<(), IoError> {
    write_triangle_mesh_as(path, mesh, PlyEncoding::BinaryLittleEndian)
}

/// [`write_triangle_mesh`] in a chosen encoding.
pub fn write_triangle_mesh_as(
    path: &Path,
    mesh: &TriangleMesh,
    encoding: PlyEncoding,
) -> Result<(), IoError> {
    writer::write_mesh(path, mesh, encoding)
}
