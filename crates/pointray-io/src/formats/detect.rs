//! Which point format a file holds, judged by its content first (extensions lie, or are
//! missing) and by its extension only when the content has no signature.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use crate::IoError;

/// The point formats pointray reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PointFormat {
    Las,
    /// LAS with a LASzip-compressed point format.
    Laz,
    Pcd,
    E57,
    Ply,
    /// Whitespace- or comma-separated text: `.xyz`, `.pts`, `.txt`, `.csv`.
    Xyz,
    /// Raw float32 LiDAR sweeps: KITTI `.bin`, nuScenes `.pcd.bin`.
    RawBin,
}

impl PointFormat {
    /// The format's usual name, for messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Las => "LAS",
            Self::Laz => "LAZ",
            Self::Pcd => "PCD",
            Self::E57 => "E57",
            Self::Ply => "PLY",
            Self::Xyz => "text points",
            Self::RawBin => "raw .bin sweep",
        }
    }
}

/// How much of the file the content checks look at.
const HEAD_BYTES: usize = 4096;

/// Offset of the point data format byte in a LAS header.
const LAS_POINT_FORMAT_OFFSET: usize = 104;

/// Detects the format of the file at `path`.
pub fn detect_format(path: &Path) -> Result<PointFormat, IoError> {
    let mut head = Vec::with_capacity(HEAD_BYTES);
    File::open(path)
        .and_then(|file| file.take(HEAD_BYTES as u64).read_to_end(&mut head))
        .map_err(|source| IoError::os(path, source))?;
    if head.is_empty() {
        return Err(IoError::malformed(path, "file is empty"));
    }
    detect_format_from(&head, path).ok_or_else(|| IoError::Unsupported {
        path: path.into(),
        what: "binary content with no known signature".into(),
        supported: "LAS/LAZ (\"LASF\"), PCD, E57 (\"ASTM-E57\"), PLY (\"ply\"), text x y z \
                    (.xyz .pts .txt .csv), raw sweeps (KITTI .bin, nuScenes .pcd.bin)"
            .into(),
    })
}

/// Detects the format from the first bytes of a file (a few KiB are enough); `path`'s
/// extension decides only for binary content without a signature.
pub fn detect_format_from(head: &[u8], path: &Path) -> Option<PointFormat> {
    signature_format(head).or_else(|| {
        if looks_like_text(head) { Some(PointFormat::Xyz) } else { binary_format_by_extension(path) }
    })
}

fn signature_format(head: &[u8]) -> Option<PointFormat> {
    if head.starts_with(b"LASF") {
        return Some(las_or_laz(head));
    }
    if head.starts_with(b"ASTM-E57") {
        return Some(PointFormat::E57);
    }
    if head.starts_with(b"ply\n") || head.starts_with(b"ply\r\n") {
        return Some(PointFormat::Ply);
    }
    is_pcd_header(head).then_some(PointFormat::Pcd)
}

/// LASzip marks compressed point formats by setting bit 7 (or bit 6, in old writers) of the
/// point format byte.
fn las_or_laz(head: &[u8]) -> PointFormat {
    match head.get(LAS_POINT_FORMAT_OFFSET) {
        Some(format) if format & 0xC0 != 0 => PointFormat::Laz,
        _ => PointFormat::Las,
    }
}

/// PCL writes "# .PCD v0.7 - Point Cloud Data file format" first; other writers start
/// straight with "VERSION". Comments may come before it.
fn is_pcd_header(head: &[u8]) -> bool {
    let text = String::from_utf8_lossy(head);
    for line in text.lines().map(str::trim).filter(|line| !line.is_empty()) {
        match line.strip_prefix('#') {
            Some(comment) if comment.trim_start().starts_with(".PCD") => return true,
            Some(_) => continue,
            None => return line.starts_with("VERSION") && text.contains("FIELDS"),
        }
    }
    false
}

/// Text if it decodes as UTF-8 (a character cut at the end of the head is fine) and holds
/// no control characters other than line breaks and tabs.
fn looks_like_text(head: &[u8]) -> bool {
    let valid = match std::str::from_utf8(head) {
        Ok(text) => text,
        Err(error) if error.error_len().is_none() => {
            match std::str::from_utf8(&head[..error.valid_up_to()]) {
                Ok(text) => text,
                Err(_) => return false,
            }
        }
        Err(_) => return false,
    };
    valid.chars().all(|c| !c.is_control() || matches!(c, '\n' | '\r' | '\t'))
}

fn binary_format_by_extension(path: &Path) -> Option<PointFormat> {
    let extension = path.extension()?.to_str()?.to_ascii_lowercase();
    match extension.as_str() {
        "bin" => Some(PointFormat::RawBin),
        _ => None,
    }
}
