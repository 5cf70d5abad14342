//! Writing outputs so that a reader never sees a half-written file and a failed write never
//! destroys what was there: write a temporary file beside the target, fsync it, rename it over.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use crate::{IoError, temporaries};

/// Writes `path` through `write`, atomically: the data goes to a temporary file in the same
/// directory (so the final rename cannot cross file systems), is synced to disk, and only then
/// replaces `path`. On any error the temporary file is removed and `path` is untouched.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> Result<(), IoError> {
    let os_error = |source| IoError::os(path, source);
    let directory = crate::folder_of(path);
    temporaries::sweep_stale(directory);
    let prefix = temporaries::prefix();
    let (file, temp_path) = temp_builder(&prefix).tempfile_in(directory).map_err(os_error)?.into_parts();
    let temporary = temp_path.to_path_buf();
    temporaries::started(&temporary);
    let written = write_and_sync(file, write).map_err(os_error);
    let result = written.and_then(|()| temp_path.persist(path).map_err(|e| os_error(e.error)));
    // Persisted, or removed when `temp_path` was dropped: either way it is no longer ours.
    temporaries::finished(&temporary);
    result
}

fn write_and_sync(file: File, write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>) -> io::Result<()> {
    let mut writer = BufWriter::with_capacity(1 << 20, file);
    write(&mut writer).and_then(|()| writer.flush())?;
    let file = writer.into_inner().map_err(|e| e.into_error())?;
    file.sync_all()
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
