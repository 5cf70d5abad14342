//! Writing outputs so that a reader never sees a half-written file and a failed write never
//! destroys what was there: write a temporary file beside the target, fsync it, rename it over.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use crate::IoError;

/// Writes `path` through `write`, atomically: the data goes to a temporary file in the same
/// directory (so the final rename cannot cross file systems), is synced to disk, and only then
/// replaces `path`. On any error the temporary file is removed and `path` is untouched.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<()>,
) -> Result<(), IoError> {
    let os_error = |source| IoError::os(path, source);
    let directory = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let (file, temp_path) = temp_builder().tempfile_in(directory).map_err(os_error)?.into_parts();
    let mut writer = BufWriter::new(file);
    write(&mut writer).and_then(|()| writer.flush()).map_err(os_error)?;
    let file = writer.into_inner().map_err(|e| os_error(e.into_error()))?;
    file.sync_all().map_err(os_error)?;
    drop(file);
    temp_path.persist(path).map_err(|e| os_error(e.error))
}

/// Hidden temporary names; on Unix the usual 0644 (less the umask) instead of tempfile's 0600,
/// since the file becomes the user's output.
fn temp_builder() -> tempfile::Builder<'static, 'static> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(".pointray-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    builder
}

/// Refuses an `output` that is the same file as `input` (same path, a symlink to it, or a hard
/// link), so that a command never overwrites what it reads. An output that does not exist yet
/// is always accepted.
pub fn ensure_not_same_file(input: &Path, output: &Path) -> Result<(), IoError> {
    let Ok(output_metadata) = std::fs::metadata(output) else {
        return Ok(());
    };
    let input_metadata = std::fs::metadata(input).map_err(|e| IoError::os(input, e))?;
    if same_file(input, output, &input_metadata, &output_metadata) {
        return Err(IoError::SameFile { input: input.into(), output: output.into() });
    }
    Ok(())
}

#[cfg(unix)]
fn same_file(_: &Path, _: &Path, input: &std::fs::Metadata, output: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    input.dev() == output.dev() && input.ino() == output.ino()
}

#[cfg(not(unix))]
fn same_file(input: &Path, output: &Path, _: &std::fs::Metadata, _: &std::fs::Metadata) -> bool {
    matches!((input.canonicalize(), output.canonicalize()), (Ok(a), Ok(b)) if a == b)
}
