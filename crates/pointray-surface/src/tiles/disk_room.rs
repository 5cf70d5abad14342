//! Whether the folders that prep in tiles writes into have room for what it will write,
//! checked before any work: a billion points sort into 36 GB of scratch beside a 31 GB store,
//! and a disk that fills after minutes of work wastes them.

use std::path::Path;

use pointray_io::disk_space::{file_system, free_bytes};
use pointray_io::{IoError, PointStream};

use crate::tiles::point_records::KEYED_POSITION_BYTES;
use crate::tiles::stream_error::StreamError;

/// The fewest bytes a point takes in a store (the compact record, before the coarse level
/// and any colours): a store's room is checked at this, so that no prep that fits is refused.
pub(crate) const STORE_POINT_BYTES: u64 = 28;

/// Bytes a file system is asked for in one folder: what for, and how many.
pub(crate) struct Need<'a> {
    pub folder: &'a Path,
    pub what: &'static str,
    pub bytes: u64,
}

/// The scratch the points of `stream` take, sorted.
pub(crate) fn sorted_points_need<'a>(stream: &PointStream, folder: &'a Path) -> Need<'a> {
    let bytes = stream.len().saturating_mul(KEYED_POSITION_BYTES + stream.attribute_bytes_per_point());
    Need { folder, what: "the sorted points", bytes }
}

/// The least room the store of `points` points takes in `folder`.
pub(crate) fn store_need(points: u64, folder: &Path) -> Need<'_> {
    Need { folder, what: "the store", bytes: points.saturating_mul(STORE_POINT_BYTES) }
}

/// Refuses, naming the folder, where the file system of some folders has less room free than
/// the needs in them add up to. File systems that do not say how much is free pass.
pub(crate) fn ensure_room(needs: &[Need]) -> Result<(), StreamError> {
    for need in needs {
        let Some((device, free)) = device_and_free(need.folder) else { continue };
        let sharing: Vec<&Need> = needs
            .iter()
            .filter(|other| device_and_free(other.folder).map(|(d, _)| d) == Some(device))
            .collect();
        if let Some(problem) = shortfall(&sharing, free) {
            return Err(StreamError::Io(IoError::unwritable(need.folder, problem)));
        }
    }
    Ok(())
}

/// Why `needs`, on one file system with `free` bytes, do not fit.
fn shortfall(needs: &[&Need], free: u64) -> Option<String> {
    let total: u64 = needs.iter().map(|need| need.bytes).sum();
    if total <= free {
        return None;
    }
    let listed: Vec<String> =
        needs.iter().map(|need| format!("{} for {}", gigabytes(need.bytes), need.what)).collect();
    Some(format!(
        "prep in tiles needs about {} on this file system ({}), which has {} free: give --scratch a \
         folder on another file system with room (a folder in memory such as /dev/shm), or free some",
        gigabytes(total),
        listed.join(" and "),
        gigabytes(free)
    ))
}

fn gigabytes(bytes: u64) -> String {
    format!("{:.1} GB", bytes as f64 / 1e9)
}

/// The folder's file system and the bytes free on it for this user.
fn device_and_free(folder: &Path) -> Option<(u64, u64)> {
    Some((file_system(folder)?, free_bytes(folder)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn needs_on_one_file_system_add_up() {
        let folder = Path::new("/data");
        let scratch = Need { folder, what: "the sorted points", bytes: 36_000_000_000 };
        let store = Need { folder, what: "the store", bytes: 28_000_000_000 };
        assert_eq!(shortfall(&[&scratch, &store], 64_000_000_000), None);
        let problem = shortfall(&[&scratch, &store], 50_000_000_000).expect("64 GB do not fit 50");
        assert!(problem.contains("about 64.0 GB"), "{problem}");
        assert!(problem.contains("36.0 GB for the sorted points and 28.0 GB for the store"), "{problem}");
        assert!(problem.contains("50.0 GB free") && problem.contains("--scratch"), "{problem}");
    }

    #[test]
    fn a_folder_with_room_passes_and_one_without_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let small = Need { folder: dir.path(), what: "the sorted points", bytes: 1 };
        assert!(ensure_room(&[small]).is_ok());
        let huge = Need { folder: dir.path(), what: "the sorted points", bytes: u64::MAX / 2 };
        let error = ensure_room(&[huge]).unwrap_err().to_string();
        assert!(error.contains(&dir.path().display().to_string()) && error.contains("free"), "{error}");
    }
}
