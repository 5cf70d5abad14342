//! Choosing a reader for a file: by content first (signatures, since extensions lie or are
//! missing), then by extension, then plain text is taken as x y z columns.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use super::columns::ColumnSpec;
use super::detect::{PointFormat, detect_format_from};
use super::{e57, las, obj, pcd, ply, raw_bin, xyz};
use crate::{IoError, PointCloud, TriangleMesh};

/// Every file format pointray reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileFormat {
    /// Read by the point formats' own detection (LAS, LAZ, PCD, E57, PLY, XYZ, KITTI).
    Points(PointFormat),
    Obj,
}

/// Extensions, consulted only when the content has no signature. To add a format: a variant,
/// a row here, and a branch in `read_point_cloud` (and `read_triangle_mesh` for meshes).
const EXTENSIONS: [(&[&str], FileFormat); 8] = [
    (&["ply"], FileFormat::Points(PointFormat::Ply)),
    (&["obj"], FileFormat::Obj),
    (&["las"], FileFormat::Points(PointFormat::Las)),
    (&["laz"], FileFormat::Points(PointFormat::Laz)),
    (&["pcd"], FileFormat::Points(PointFormat::Pcd)),
    (&["e57"], FileFormat::Points(PointFormat::E57)),
    (&["xyz", "pts", "txt", "csv"], FileFormat::Points(PointFormat::Xyz)),
    (&["bin"], FileFormat::Points(PointFormat::RawBin)),
];

const SUPPORTED: &str = "PLY (.ply), OBJ (.obj), LAS/LAZ (.las .laz), PCD (.pcd), E57 (.e57), \
                         text x y z (.xyz .pts .txt .csv), raw sweeps (KITTI .bin, nuScenes .pcd.bin)";
const SUPPORTED_MESHES: &str = "PLY with faces (.ply), OBJ (.obj)";

/// How much of the file the content checks look at.
const HEAD_BYTES: u64 = 4096;

/// Reads a point cloud from any supported format.
pub fn read_point_cloud(path: &Path) -> Result<PointCloud, IoError> {
    read_point_cloud_with(path, None)
}

/// Reads a point cloud, with `columns` saying what each column holds in a format that does
/// not name its columns (text, raw `.bin` sweeps); other formats name their own fields and
/// refuse a column spec rather than ignore it.
pub fn read_point_cloud_with(path: &Path, columns: Option<&ColumnSpec>) -> Result<PointCloud, IoError> {
    let format = detect_file_format(path)?;
    if let Some(spec) = columns
        && !matches!(format, FileFormat::Points(PointFormat::Xyz | PointFormat::RawBin))
    {
        return Err(IoError::Unsupported {
            path: path.into(),
            what: format!("column spec {spec} for a {} file, which names its own fields", format.name()),
            supported: "column specs for text points (.xyz .pts .txt .csv) and raw sweeps (.bin)".into(),
        });
    }
    match format {
        FileFormat::Obj => obj::read_point_cloud(path),
        FileFormat::Points(format) => match format {
            PointFormat::Ply => ply::read_point_cloud(path),
            PointFormat::Las | PointFormat::Laz => las::read_las(path),
            PointFormat::Pcd => pcd::read_pcd(path),
            PointFormat::E57 => e57::read_e57(path),
            PointFormat::Xyz => xyz::read_xyz(path, columns),
            PointFormat::RawBin => raw_bin::read_raw_bin(path, columns),
        },
    }
}

/// Reads a triangle mesh (PLY with a face element, or OBJ).
pub fn read_triangle_mesh(path: &Path) -> Result<TriangleMesh, IoError> {
    match detect_file_format(path)? {
        FileFormat::Points(PointFormat::Ply) => ply::read_triangle_mesh(path),
        FileFormat::Obj => obj::read_triangle_mesh(path),
        FileFormat::Points(other) => Err(IoError::Unsupported {
            path: path.into(),
            what: format!("mesh format ({other:?} holds points only)"),
            supported: SUPPORTED_MESHES.into(),
        }),
    }
}

impl FileFormat {
    /// The format's usual name, for messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Obj => "OBJ",
            Self::Points(format) => format.name(),
        }
    }
}

/// The format of the file at `path`, judged as the module doc says.
pub fn detect_file_format(path: &Path) -> Result<FileFormat, IoError> {
    crate::ensure_readable_file(path)?;
    let mut head = Vec::new();
    File::open(path)
        .and_then(|file| file.take(HEAD_BYTES).read_to_end(&mut head))
        .map_err(|source| IoError::os(path, source))?;
    format_of(&head, path).ok_or_else(|| IoError::Unsupported {
        path: path.into(),
        what: "file format (no known signature or extension)".into(),
        supported: SUPPORTED.into(),
    })
}

/// Detection on the first bytes. An empty head falls through to the extension, so that the
/// format's own reader reports the empty file.
fn format_of(head: &[u8], path: &Path) -> Option<FileFormat> {
    // With no path, the point detection answers from content alone: a signature, or text.
    let by_content = (!head.is_empty()).then(|| detect_format_from(head, Path::new(""))).flatten();
    let signature = by_content.filter(|format| *format != PointFormat::Xyz).map(FileFormat::Points);
    let obj = obj::has_signature(head).then_some(FileFormat::Obj);
    let text = by_content.map(FileFormat::Points);
    signature.or(obj).or_else(|| by_extension(path)).or(text)
}

fn by_extension(path: &Path) -> Option<FileFormat> {
    let extension = path.extension()?.to_str()?.to_ascii_lowercase();
    EXTENSIONS.iter().find(|(names, _)| names.contains(&extension.as_str())).map(|(_, format)| *format)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn content_decides_before_the_extension() {
        let ply = FileFormat::Points(PointFormat::Ply);
        assert_eq!(format_of(b"ply\nformat ascii 1.0\n", Path::new("a.obj")), Some(ply));
        assert_eq!(format_of(b"# exported\nv 0 0 0\n", Path::new("a.ply")), Some(FileFormat::Obj));
        assert_eq!(format_of(b"v 0 0 0\nf 1 1 1\n", Path::new("noext")), Some(FileFormat::Obj));
    }

    #[test]
    fn the_extension_decides_when_content_cannot() {
        assert_eq!(format_of(b"", Path::new("empty.PLY")), Some(FileFormat::Points(PointFormat::Ply)));
        assert_eq!(
            format_of(b"solid x\n", Path::new("fake.ply")),
            Some(FileFormat::Points(PointFormat::Ply))
        );
        assert_eq!(format_of(b"1 2 3\n", Path::new("cloud")), Some(FileFormat::Points(PointFormat::Xyz)));
        assert_eq!(format_of(&[0, 1, 2, 0xff], Path::new("cloud.dat")), None);
    }
}
