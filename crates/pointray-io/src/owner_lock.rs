//! The lock by which a temporary's owner shows that it still runs: an exclusive `flock`
//! (`File::try_lock`) that the owner takes on the file as soon as it exists and holds until
//! the file is closed. The kernel (or, on NFS, the lock manager) releases it when the owner
//! exits, however it exits. It is seen from every PID namespace of the kernel and, on file
//! systems whose locks reach every host (NFS, CephFS, GPFS, Lustre mounted with `flock`), from
//! every host.

use std::fs::{File, OpenOptions, TryLockError};
use std::path::Path;

/// What a sweep learns from a temporary's lock.
#[derive(Debug)]
pub(crate) enum Lock {
    /// The lock was free and is now the sweeper's, until this is dropped: no owner holds it.
    Taken { _held: File },
    /// An owner holds it.
    Held,
    /// The file could not be opened or the file system does not lock.
    Unknown,
}

/// Takes the lock of `file`, just made at `path`, and checks that no sweep removed it before.
/// `false` when a sweep did or is about to (it holds the lock): make another. Where the file
/// system has no locks the file goes unlocked, and sweeps treat it as they treat the
/// temporaries of writers on another host.
pub(crate) fn claim(file: &File, path: &Path) -> bool {
    let taken_by_a_sweep = matches!(file.try_lock(), Err(TryLockError::WouldBlock));
    !taken_by_a_sweep && still_named(file, path)
}

/// Tries, without waiting, to take the lock of the file at `path`.
pub(crate) fn try_take(path: &Path) -> Lock {
    // Opened for writing: NFS turns `flock` into a byte-range lock, whose exclusive kind needs a
    // descriptor open for writing. Opening does not truncate or touch the file.
    let Ok(file) = OpenOptions::new().write(true).open(path) else { return Lock::Unknown };
    match file.try_lock() {
        Ok(()) => Lock::Taken { _held: file },
        Err(TryLockError::WouldBlock) => Lock::Held,
        Err(TryLockError::Error(_)) => Lock::Unknown,
    }
}

/// Whether `path` still names the file `file` is open on.
fn still_named(file: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let (Ok(open), Ok(named)) = (file.metadata(), std::fs::metadata(path)) else { return false };
        open.dev() == named.dev() && open.ino() == named.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = file;
        path.exists()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_held_lock_is_seen_from_another_descriptor_and_freed_on_close() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("owned");
        let owner = File::create(&path).unwrap();
        assert!(claim(&owner, &path));
        assert!(matches!(try_take(&path), Lock::Held));
        drop(owner);
        let sweep = try_take(&path);
        assert!(matches!(sweep, Lock::Taken { .. }), "the lock is free once closed");
        assert!(!claim(&File::open(&path).unwrap(), &path), "a sweep holds the lock");
    }

    #[test]
    fn a_file_removed_before_its_lock_is_not_claimed() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("owned");
        let owner = File::create(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert!(!claim(&owner, &path));
        std::fs::write(&path, b"another file of the same name").unwrap();
        assert!(!claim(&owner, &path));
    }
}
