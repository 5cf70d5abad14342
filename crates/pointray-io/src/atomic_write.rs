//! Writing outputs so that a reader never sees a half-written file and a failed write never
//! destroys what was there: write a temporary file beside the target, fsync it, rename it over.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use tempfile::TempPath;

use crate::{IoError, owner_lock, temporaries};

/// Writes `path` through `write`, atomically: the data goes to a temporary file in the same
/// directory (so the final rename cannot cross file systems), is synced to disk, and only then
/// replaces `path`. On any error the temporary file is removed and `path` is untouched.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> Result<(), IoError> {
    let output = AtomicFile::create(path)?;
    let written = output.file().try_clone().and_then(|file| {
        let mut writer = BufWriter::with_capacity(1 << 20, file);
        write(&mut writer).and_then(|()| writer.flush())
    });
    written.map_err(|source| IoError::os(path, source))?;
    output.commit()
}

/// An output written in place, at any offsets and for as long as its writer likes, that
/// replaces its target only when committed: a temporary file beside the target, removed if
/// dropped uncommitted, and locked while open so that no other process's sweep removes it
/// (`temporaries`).
pub struct AtomicFile {
    file: File,
    /// `None` once committed.
    temporary: Option<TempPath>,
    temporary_name: PathBuf,
    target: PathBuf,
}

impl AtomicFile {
    /// A temporary file that will become `path`.
    pub fn create(path: &Path) -> Result<Self, IoError> {
        let directory = crate::folder_of(path);
        temporaries::sweep_stale(directory);
        let prefix = temporaries::prefix();
        let make = || temp_builder(&prefix).tempfile_in(directory);
        let claim = |made: &tempfile::NamedTempFile| owner_lock::claim(made.as_file(), made.path());
        let (file, temporary) =
            temporaries::claimed(make, claim).map_err(|e| IoError::os(path, e))?.into_parts();
        let temporary_name = temporary.to_path_buf();
        temporaries::started(&temporary_name);
        Ok(Self { file, temporary: Some(temporary), temporary_name, target: path.to_path_buf() })
    }

    /// The file to write; positioned writes (`FileExt::write_all_at`) may come from any thread.
    pub fn file(&self) -> &File {
        &self.file
    }

    /// The path the file will have once committed.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Starts writing `length` bytes from `offset` to disk without waiting for them, so that
    /// the sync on commit finds little left to write. Where the system offers no such call it
    /// does nothing: the commit syncs the file whole either way.
    pub fn start_writeback(&self, offset: u64, length: u64) {
        #[cfg(target_os = "linux")]
        {
            use std::os::fd::AsRawFd;
            // A length of 0 would mean the whole rest of the file.
            let (Ok(offset), Ok(length @ 1..)) = (i64::try_from(offset), i64::try_from(length)) else {
                return;
            };
            // SAFETY: the descriptor is this file's own, open for as long as `self`. The
            // result is ignored: the call only hastens what `commit`'s sync does anyway.
            unsafe {
                libc::sync_file_range(self.file.as_raw_fd(), offset, length, libc::SYNC_FILE_RANGE_WRITE);
            }
        }
    }

    /// Syncs the file to disk and renames it over its target.
    pub fn commit(mut self) -> Result<(), IoError> {
        let os_error = |source| IoError::os(&self.target, source);
        self.file.sync_all().map_err(os_error)?;
        let temporary = self.temporary.take().expect("an uncommitted file has its temporary");
        temporary.persist(&self.target).map_err(|e| os_error(e.error))
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        // Removes an uncommitted temporary before it stops being ours.
        drop(self.temporary.take());
        temporaries::finished(&self.temporary_name);
    }
}

/// Hidden temporary names; on Unix the usual 0644 (less the umask) instead of tempfile's 0600,
/// since the file becomes the user's output.
fn temp_builder(prefix: &str) -> tempfile::Builder<'_, 'static> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(prefix).suffix(temporaries::SUFFIX);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    builder
}
