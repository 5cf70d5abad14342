//! How much room a folder's file system has: what prep in tiles and the scale benchmark check
//! before they write gigabytes.

use std::os::unix::fs::MetadataExt;
use std::path::Path;

/// The file system that holds `path`, as a number equal for paths on the same one; `None`
/// where `path` cannot be looked at.
pub fn file_system(path: &Path) -> Option<u64> {
    std::fs::metadata(path).ok().map(|metadata| metadata.dev())
}

/// The bytes free for this user on the file system that holds `folder`; `None` where the
/// system does not say.
pub fn free_bytes(folder: &Path) -> Option<u64> {
    let stats = rustix::fs::statvfs(folder).ok()?;
    Some(stats.f_bavail.saturating_mul(stats.f_frsize))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_has_room_and_a_missing_one_has_no_answer() {
        let folder = tempfile::tempdir().expect("a temporary folder");
        assert!(free_bytes(folder.path()).is_some_and(|bytes| bytes > 0));
        assert_eq!(free_bytes(&folder.path().join("absent")), None);
        let file = folder.path().join("file");
        std::fs::write(&file, b"x").expect("a file");
        assert!(file_system(&file).is_some() && file_system(&file) == file_system(folder.path()));
        assert_eq!(file_system(&folder.path().join("absent")), None);
    }
}
