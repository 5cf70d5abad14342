//! The temporary files behind atomic writes, and the temporary folders of out-of-core work.
//! Each is named `.pointray-PID-XXXXXX.tmp` after the process that writes it, so that:
//! - a process stopped by SIGINT or SIGTERM removes its own (`remove_live`, which the
//!   command-line tool calls from its signal handler);
//! - a later write into the same folder removes those of processes that no longer run (killed
//!   with SIGKILL, or by a power cut), and never another running process's.

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

const PREFIX: &str = ".pointray-";
pub(crate) const SUFFIX: &str = ".tmp";

/// Temporary files this process is writing now.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Folders already swept for stale temporaries by this process.
static SWEPT: Mutex<Option<HashSet<PathBuf>>> = Mutex::new(None);

/// The start of this process's temporary names; `SUFFIX` ends them.
pub(crate) fn prefix() -> String {
    format!("{PREFIX}{}-", std::process::id())
}

/// Notes that `path` is being written, until `finished` is called with it.
pub(crate) fn started(path: &Path) {
    lock(&LIVE).push(path.to_path_buf());
}

pub(crate) fn finished(path: &Path) {
    lock(&LIVE).retain(|live| live != path);
}

/// Removes every temporary file and folder this process is writing now: for a signal
/// handler, just before the process exits.
pub fn remove_live() {
    for path in lock(&LIVE).drain(..) {
        remove(&path);
    }
}

fn remove(path: &Path) {
    let _ = if path.is_dir() { std::fs::remove_dir_all(path) } else { std::fs::remove_file(path) };
}

/// A folder for a process's scratch files (named as the temporary files are), removed when
/// dropped, on SIGINT or SIGTERM (`remove_live`), or by a later sweep once its process is
/// gone.
#[derive(Debug)]
pub struct TemporaryFolder {
    path: PathBuf,
}

impl TemporaryFolder {
    /// A new folder inside `parent`.
    pub fn new_in(parent: &Path) -> Result<Self, crate::IoError> {
        sweep_stale(parent);
        let folder = tempfile::Builder::new()
            .prefix(&prefix())
            .suffix(SUFFIX)
            .tempdir_in(parent)
            .map_err(|source| crate::IoError::os(parent, source))?;
        let path = folder.keep();
        started(&path);
        Ok(Self { path })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for TemporaryFolder {
    fn drop(&mut self) {
        remove(&self.path);
        finished(&self.path);
    }
}

/// Removes, once per folder and process, the temporaries in `folder` left by processes that
/// no longer run.
pub(crate) fn sweep_stale(folder: &Path) {
    let key = folder.canonicalize().unwrap_or_else(|_| folder.to_path_buf());
    if !lock(&SWEPT).get_or_insert_with(HashSet::new).insert(key) {
        return;
    }
    let Ok(entries) = std::fs::read_dir(folder) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let stale = name.to_str().and_then(writer_pid).is_some_and(|pid| !process_runs(pid));
        if stale {
            remove(&entry.path());
        }
    }
}

/// The process id in one of our temporary names.
fn writer_pid(name: &str) -> Option<u32> {
    let (pid, _) = name.strip_prefix(PREFIX)?.strip_suffix(SUFFIX)?.split_once('-')?;
    pid.parse().ok()
}

/// Whether `pid` runs; where the system cannot say, every process is taken to run, so that
/// nothing is removed on a guess.
fn process_runs(pid: u32) -> bool {
    let proc = Path::new("/proc");
    !proc.join("self").exists() || proc.join(pid.to_string()).exists()
}

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_carry_the_writer_pid() {
        assert_eq!(writer_pid(".pointray-4242-a1B2c3.tmp"), Some(4242));
        assert_eq!(writer_pid(".pointray-a1B2c3.tmp"), None);
        assert_eq!(writer_pid("out.png"), None);
        assert!(process_runs(std::process::id()));
    }

    #[test]
    fn a_handler_removes_the_temporaries_being_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(format!("{}AbCdEf{SUFFIX}", prefix()));
        std::fs::write(&path, b"half").unwrap();
        started(&path);
        remove_live();
        assert!(!path.exists());
        finished(&path);
    }

    #[test]
    fn a_temporary_folder_goes_with_its_contents() {
        let dir = tempfile::tempdir().unwrap();
        let folder = TemporaryFolder::new_in(dir.path()).unwrap();
        let path = folder.path().to_path_buf();
        std::fs::write(path.join("run-0"), b"sorted").unwrap();
        assert!(writer_pid(path.file_name().unwrap().to_str().unwrap()).is_some(), "{path:?}");
        drop(folder);
        assert!(!path.exists());
    }
}
