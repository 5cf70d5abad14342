//! The temporary files behind atomic writes, and the temporary folders of out-of-core work.
//! Each is named `.pointray-PID-KERNEL-XXXXXX.tmp` after the process that writes it and the
//! kernel that process runs on (`KERNEL`: the start of the kernel's boot id, the same in every
//! container of one machine), and its writer holds its lock (`owner_lock`; a folder's is on its
//! `OWNER_LOCK` file) from the moment it exists. So:
//! - a process stopped by SIGINT or SIGTERM removes its own (`remove_live`, which the
//!   command-line tool calls from its signal handler);
//! - a later write into the same folder removes a temporary only when its writer is known to
//!   be gone, whichever host or PID namespace that writer runs in (`stale`).

use std::collections::HashSet;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, OnceLock};
use std::time::{Duration, SystemTime};

use crate::owner_lock::{self, Lock};

const PREFIX: &str = ".pointray-";
pub(crate) const SUFFIX: &str = ".tmp";

/// Temporary files this process is writing now.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Folders already swept for stale temporaries by this process.
static SWEPT: Mutex<Option<HashSet<PathBuf>>> = Mutex::new(None);

/// The file inside a temporary folder whose lock its writer holds: a folder cannot be opened
/// for writing, which a lock on NFS needs.
const OWNER_LOCK: &str = "owner.lock";

/// How long a temporary whose writer may be on another host must lie untouched before a sweep
/// may remove it. Where locks reach every host a free lock would do, but some shared file
/// systems keep locks to one host (NFS mounted with `local_lock`, Lustre with `localflock`),
/// and there a free lock says nothing. A day is far beyond any run: a billion points prep in
/// under 9 minutes, and a prep writes its temporaries as it goes.
const FOREIGN_STALE_AFTER: Duration = Duration::from_secs(24 * 60 * 60);

/// The start of this process's temporary names; `SUFFIX` ends them.
pub(crate) fn prefix() -> String {
    format!("{PREFIX}{}-{}-", std::process::id(), kernel_tag().unwrap_or("unknown"))
}

/// This kernel's tag: the first 8 hex digits of its boot id, which differs between machines
/// and boots but not between containers or PID namespaces. `None` where there is no boot id.
fn kernel_tag() -> Option<&'static str> {
    static TAG: OnceLock<Option<String>> = OnceLock::new();
    TAG.get_or_init(|| {
        let boot_id = std::fs::read_to_string("/proc/sys/kernel/random/boot_id").ok()?;
        let tag: String = boot_id.chars().filter(char::is_ascii_hexdigit).take(8).collect();
        (tag.len() == 8).then_some(tag)
    })
    .as_deref()
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
    /// Open, and so locked, for as long as the folder is in use.
    _owner_lock: File,
}

impl TemporaryFolder {
    /// A new folder inside `parent`.
    pub fn new_in(parent: &Path) -> Result<Self, crate::IoError> {
        sweep_stale(parent);
        let make = || {
            let folder = tempfile::Builder::new().prefix(&prefix()).suffix(SUFFIX).tempdir_in(parent)?;
            let lock = File::create(folder.path().join(OWNER_LOCK))?;
            Ok((folder, lock))
        };
        let claim = |(folder, lock): &(tempfile::TempDir, File)| {
            owner_lock::claim(lock, &folder.path().join(OWNER_LOCK))
        };
        let (folder, lock) = claimed(make, claim).map_err(|source| crate::IoError::os(parent, source))?;
        let path = folder.keep();
        started(&path);
        Ok(Self { path, _owner_lock: lock })
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

/// Makes temporaries with `make` until `claim` finds this process's lock on one. A sweep from
/// another PID namespace may remove a temporary between its creation and its lock; each one
/// lost that way is dropped and another made under a new name.
pub(crate) fn claimed<T>(
    mut make: impl FnMut() -> std::io::Result<T>,
    claim: impl Fn(&T) -> bool,
) -> std::io::Result<T> {
    const ATTEMPTS: usize = 8;
    for _ in 0..ATTEMPTS {
        let made = make()?;
        if claim(&made) {
            return Ok(made);
        }
    }
    Err(std::io::Error::other("other processes removed every temporary made here as soon as it was made"))
}

/// Removes, once per folder and process, the temporaries in `folder` whose writers are gone.
pub(crate) fn sweep_stale(folder: &Path) {
    let key = folder.canonicalize().unwrap_or_else(|_| folder.to_path_buf());
    if lock(&SWEPT).get_or_insert_with(HashSet::new).insert(key) {
        sweep(folder);
    }
}

fn sweep(folder: &Path) {
    let Ok(entries) = std::fs::read_dir(folder) else { return };
    for entry in entries.flatten() {
        let Some(written_here) = entry.file_name().to_str().and_then(written_on_this_kernel) else {
            continue;
        };
        let path = entry.path();
        // The lock stays taken until the temporary is gone, so that no writer can claim it.
        let lock = owner_lock::try_take(&lock_file(&path));
        if stale(&path, &lock, written_here) {
            remove(&path);
        }
    }
}

/// Whether a temporary's writer is known to be gone. A free lock proves it where the writer
/// ran on this kernel. A writer on another host (or a pointray from before the locks) is taken
/// to be gone only once its temporary has lain untouched for `FOREIGN_STALE_AFTER` too, and so
/// is one whose lock cannot be read.
fn stale(path: &Path, lock: &Lock, written_here: bool) -> bool {
    match lock {
        Lock::Held => false,
        Lock::Taken { .. } if written_here => true,
        Lock::Taken { .. } | Lock::Unknown => untouched_for(path, FOREIGN_STALE_AFTER),
    }
}

/// For one of our temporaries' names, whether its writer ran on this kernel; `None` for other
/// names.
fn written_on_this_kernel(name: &str) -> Option<bool> {
    let mut parts = name.strip_prefix(PREFIX)?.strip_suffix(SUFFIX)?.split('-');
    parts.next()?.parse::<u32>().ok()?;
    // Names from before the kernel tag have only the process id and the random part.
    let kernel = match (parts.next(), parts.next()) {
        (Some(kernel), Some(_random)) => Some(kernel),
        _ => None,
    };
    Some(kernel.is_some_and(|kernel| Some(kernel) == kernel_tag()))
}

/// The file whose lock a temporary's writer holds.
fn lock_file(path: &Path) -> PathBuf {
    if path.is_dir() { path.join(OWNER_LOCK) } else { path.to_path_buf() }
}

/// Whether neither `path` nor, for a folder, anything directly in it has been modified for
/// `age`. Anything unreadable counts as touched.
fn untouched_for(path: &Path, age: Duration) -> bool {
    let modified = |path: &Path| std::fs::metadata(path).and_then(|m| m.modified()).ok();
    let old = |time: Option<SystemTime>| {
        time.and_then(|time| SystemTime::now().duration_since(time).ok()).is_some_and(|since| since > age)
    };
    let inside = || -> Option<bool> {
        let entries = std::fs::read_dir(path).ok()?;
        Some(entries.flatten().all(|entry| old(modified(&entry.path()))))
    };
    old(modified(path)) && (!path.is_dir() || inside() == Some(true))
}

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A name for a temporary written by `pid` on the kernel tagged `kernel`.
    fn name(pid: u32, kernel: &str) -> String {
        format!("{PREFIX}{pid}-{kernel}-AbCdEf{SUFFIX}")
    }

    /// Above Linux's largest process id (2^22), so no process here can have it.
    const NO_SUCH_PID: u32 = 4_194_305;

    fn another_kernel() -> &'static str {
        if kernel_tag() == Some("0badf00d") { "deadbeef" } else { "0badf00d" }
    }

    fn age(path: &Path, by: Duration) {
        let file = File::options().write(true).open(path).unwrap();
        file.set_modified(SystemTime::now() - by).unwrap();
    }

    #[test]
    fn names_say_whether_their_writer_ran_on_this_kernel() {
        assert_eq!(written_on_this_kernel(&format!("{}AbCdEf{SUFFIX}", prefix())), Some(true));
        assert_eq!(written_on_this_kernel(&name(4242, another_kernel())), Some(false));
        assert_eq!(written_on_this_kernel(".pointray-4242-a1B2c3.tmp"), Some(false));
        assert_eq!(written_on_this_kernel(".pointray-a1B2c3.tmp"), None);
        assert_eq!(written_on_this_kernel("out.png"), None);
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_locked_temporary_survives_a_sweep_though_its_pid_runs_nowhere_here() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name(NO_SUCH_PID, kernel_tag().unwrap()));
        // A writer in another PID namespace: its process id means nothing here, its lock does.
        let writer = File::create(&path).unwrap();
        writer.lock().unwrap();
        sweep(dir.path());
        assert!(path.exists(), "a live writer's temporary is kept");
        drop(writer);
        sweep(dir.path());
        assert!(!path.exists(), "once its lock is free, the writer is gone");
    }

    #[test]
    fn another_hosts_temporary_goes_only_when_free_and_a_day_untouched() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name(NO_SUCH_PID, another_kernel()));
        std::fs::write(&path, b"partial").unwrap();
        sweep(dir.path());
        assert!(path.exists(), "its lock may be one this host cannot see");
        age(&path, 2 * FOREIGN_STALE_AFTER);
        let writer = File::open(&path).unwrap();
        writer.lock_shared().unwrap();
        sweep(dir.path());
        assert!(path.exists(), "a held lock keeps it at any age");
        drop(writer);
        sweep(dir.path());
        assert!(!path.exists());
    }

    #[test]
    fn a_live_temporary_folder_survives_a_sweep_and_an_unlocked_new_one_too() {
        let dir = tempfile::tempdir().unwrap();
        let live = TemporaryFolder::new_in(dir.path()).unwrap();
        // A folder made by a writer that has not yet made its lock file, or by an old pointray.
        let unlocked = dir.path().join(name(NO_SUCH_PID, kernel_tag().unwrap_or("unknown")));
        std::fs::create_dir(&unlocked).unwrap();
        sweep(dir.path());
        assert!(live.path().exists() && unlocked.exists());
    }

    #[test]
    fn a_temporary_removed_before_its_lock_is_made_again() {
        let dir = tempfile::tempdir().unwrap();
        let mut attempts = 0;
        let make = || {
            attempts += 1;
            let path = dir.path().join(format!("attempt-{attempts}"));
            let file = File::create(&path)?;
            if attempts == 1 {
                // A sweep elsewhere removes the first one before its writer locks it.
                std::fs::remove_file(&path)?;
            }
            Ok((file, path))
        };
        let (_, path) = claimed(make, |(file, path)| owner_lock::claim(file, path)).unwrap();
        assert!(path.ends_with("attempt-2"), "{path:?}");
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
        let name = path.file_name().unwrap().to_str().unwrap();
        assert!(written_on_this_kernel(name).is_some(), "{path:?}");
        drop(folder);
        assert!(!path.exists());
    }
}
