//! Which paths a command may read and write: an input must be a regular file, and an output
//! must not be an input (the same path, a symlink to it or a hard link), a folder or a device,
//! and its folder must exist. Commands check their outputs before any slow work, so that a
//! typo fails at once and nothing they read is ever replaced.

use std::fs::Metadata;
use std::path::{Path, PathBuf};

use crate::IoError;

/// An input that can be read as a file: it exists and is neither a folder nor a device, pipe
/// or socket (reading `/dev/zero` would never end).
pub fn ensure_readable_file(path: &Path) -> Result<(), IoError> {
    match std::fs::metadata(path) {
        Ok(metadata) if metadata.is_file() => Ok(()),
        Ok(metadata) => Err(IoError::unusable(path, format!("is {}, not a file", kind_of(&metadata)))),
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => {
            Err(IoError::unusable(path, "file not found"))
        }
        Err(error) => Err(IoError::os(path, error)),
    }
}

/// An output path that a write may replace: not a folder, device, pipe or socket, in a
/// folder that exists, and not ending in a separator (`out.png/` names a folder).
pub fn ensure_writable_output(path: &Path) -> Result<(), IoError> {
    let last = path.as_os_str().as_encoded_bytes().last();
    if last.is_some_and(|&byte| std::path::is_separator(char::from(byte))) {
        return Err(IoError::unusable(path, "ends with a path separator; an output must be a file"));
    }
    if let Ok(metadata) = std::fs::metadata(path)
        && !metadata.is_file()
    {
        return Err(IoError::unusable(path, format!("is {}; an output must be a file", kind_of(&metadata))));
    }
    let folder = folder_of(path);
    match std::fs::metadata(folder) {
        Ok(metadata) if metadata.is_dir() => Ok(()),
        Ok(_) => Err(IoError::unusable(path, format!("{} is not a folder", folder.display()))),
        Err(_) => Err(IoError::unusable(path, format!("the folder {} does not exist", folder.display()))),
    }
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

/// `ensure_writable_output` for each of `outputs`, `ensure_not_same_file` against each of
/// `inputs` that exists (one that does not cannot be lost), and no two outputs one file (the
/// second would replace the first).
pub fn ensure_outputs_spare_inputs(inputs: &[PathBuf], outputs: &[PathBuf]) -> Result<(), IoError> {
    for (index, output) in outputs.iter().enumerate() {
        ensure_writable_output(output)?;
        for input in inputs.iter().filter(|input| input.exists()) {
            ensure_not_same_file(input, output)?;
        }
        if let Some(earlier) = outputs[..index].iter().find(|earlier| one_target(earlier, output)) {
            let problem =
                format!("is also the output {}; each output needs a file of its own", earlier.display());
            return Err(IoError::unusable(output, problem));
        }
    }
    Ok(())
}

/// Whether writing `a` and `b` writes one file: links to one existing file, or one name in one
/// folder (the folders compared with their links resolved).
fn one_target(a: &Path, b: &Path) -> bool {
    if let (Ok(a_metadata), Ok(b_metadata)) = (std::fs::metadata(a), std::fs::metadata(b)) {
        return same_file(a, b, &a_metadata, &b_metadata);
    }
    let resolved = |path: &Path| Some(folder_of(path).canonicalize().ok()?.join(path.file_name()?));
    matches!((resolved(a), resolved(b)), (Some(a), Some(b)) if a == b)
}

/// The folder a file goes in; `.` for a bare file name.
pub fn folder_of(path: &Path) -> &Path {
    path.parent().filter(|parent| !parent.as_os_str().is_empty()).unwrap_or(Path::new("."))
}

fn kind_of(metadata: &Metadata) -> &'static str {
    if metadata.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let kind = metadata.file_type();
        if kind.is_block_device() || kind.is_char_device() {
            return "a device";
        }
        if kind.is_fifo() {
            return "a pipe";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

#[cfg(unix)]
fn same_file(_: &Path, _: &Path, input: &Metadata, output: &Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    input.dev() == output.dev() && input.ino() == output.ino()
}

#[cfg(not(unix))]
fn same_file(input: &Path, output: &Path, _: &Metadata, _: &Metadata) -> bool {
    matches!((input.canonicalize(), output.canonicalize()), (Ok(a), Ok(b)) if a == b)
}
