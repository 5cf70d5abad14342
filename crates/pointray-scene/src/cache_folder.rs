//! The folder of cached point sets. The cache tags it (`CACHEDIR.TAG`, which also tells backup
//! tools to skip it) and lists every entry it writes there, so that `cache clean` touches only
//! folders the cache made, and in them only files the cache wrote: a folder may hold the
//! user's own stores, named like entries or not.

use std::collections::HashSet;
use std::io::{self, Write};
use std::path::Path;

use pointray_io::IoError;

const TAG_NAME: &str = "CACHEDIR.TAG";

/// The signature every cache-directory tag starts with (<https://bford.info/cachedir/>), then
/// the line by which pointray knows its own tag from other programs'.
const TAG: &str = "Signature: 8a477f597d28d172789f06886806bc55\n\
                   # This file is a cache directory tag created by pointray for its cached point sets.\n\
                   # For information about cache directory tags, see https://bford.info/cachedir/\n";

/// The entries the cache wrote, one file name a line.
const ENTRIES_NAME: &str = "pointray-cache-entries.txt";

/// The folder `render` makes beside its images. Caches made before the tag are known by this
/// name alone, and in them every file named as an entry is taken for one.
const DEFAULT_NAME: &str = ".pointray-cache";

/// Makes `dir` (and its parents) and tags it as the cache's, unless it has a tag already.
pub(crate) fn make(dir: &Path) -> io::Result<()> {
    std::fs::create_dir_all(dir)?;
    match std::fs::File::create_new(dir.join(TAG_NAME)) {
        Ok(mut tag) => tag.write_all(TAG.as_bytes()),
        Err(error) if error.kind() == io::ErrorKind::AlreadyExists => Ok(()),
        Err(error) => Err(error),
    }
}

/// Lists `name` among the entries the cache wrote in `dir`. One short append, which
/// concurrent writers' appends do not interleave with.
pub(crate) fn record(dir: &Path, name: &str) -> io::Result<()> {
    let mut entries = std::fs::OpenOptions::new().append(true).create(true).open(dir.join(ENTRIES_NAME))?;
    entries.write_all(format!("{name}\n").as_bytes())
}

/// Removes the entries the cache wrote in `cache_dir`, and the folder itself once nothing else
/// is left in it (an untagged folder from before the tag, once empty). Returns the files removed and their bytes. A folder the cache did not make
/// is refused, and nothing in it removed.
pub fn clean_cache(cache_dir: &Path) -> Result<(usize, u64), IoError> {
    let entries = written_entries(cache_dir)?;
    let mut removed = (0, 0);
    for name in entries.iter().filter(|name| is_cache_file_name(name)) {
        let path = cache_dir.join(name);
        let Ok(metadata) = std::fs::symlink_metadata(&path) else { continue };
        if metadata.is_file() {
            std::fs::remove_file(&path).map_err(|e| IoError::os(&path, e))?;
            removed = (removed.0 + 1, removed.1 + metadata.len());
        }
    }
    // Every entry listed is gone; an entry written while this ran goes unlisted, and so stays.
    let _ = std::fs::remove_file(cache_dir.join(ENTRIES_NAME));
    remove_if_only_the_tag(cache_dir);
    Ok(removed)
}

/// The names of the entries the cache wrote in `dir`: those its list holds, or in a cache
/// from before the list, every name in it.
fn written_entries(dir: &Path) -> Result<HashSet<String>, IoError> {
    let os_error = |source| IoError::os(dir, source);
    match std::fs::read_to_string(dir.join(ENTRIES_NAME)) {
        Ok(text) => return Ok(text.lines().map(str::to_owned).collect()),
        Err(error) if error.kind() != io::ErrorKind::NotFound => {
            return Err(IoError::os(dir.join(ENTRIES_NAME), error));
        }
        Err(_) if is_tagged(dir) => return Ok(HashSet::new()),
        Err(_) => {}
    }
    if dir.file_name().is_some_and(|name| name == DEFAULT_NAME) {
        let names = std::fs::read_dir(dir).map_err(os_error)?.flatten();
        return Ok(names.filter_map(|entry| entry.file_name().into_string().ok()).collect());
    }
    std::fs::metadata(dir).map_err(os_error)?;
    Err(IoError::unusable(
        dir,
        "is not a pointray cache folder: the cache's CACHEDIR.TAG and its list of entries are \
         not in it; nothing was removed",
    ))
}

/// Whether `dir` holds the tag pointray writes (another program's tag is not ours to remove).
fn is_tagged(dir: &Path) -> bool {
    std::fs::read_to_string(dir.join(TAG_NAME)).is_ok_and(|text| text == TAG)
}

/// Removes our tag and the folder when nothing else is left in it.
fn remove_if_only_the_tag(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let ours = is_tagged(dir);
    if entries.flatten().all(|entry| ours && entry.file_name() == TAG_NAME) {
        let _ = std::fs::remove_file(dir.join(TAG_NAME));
        // `remove_dir` refuses a folder that something was written into meanwhile.
        let _ = std::fs::remove_dir(dir);
    }
}

/// `STEM-0123456789abcdef.patches`, as `point_sets` names entries.
fn is_cache_file_name(name: &str) -> bool {
    let Some(rest) = name.strip_suffix(".patches") else { return false };
    let key = rest.rsplit_once('-').map_or("", |(_, key)| key);
    key.len() == 16 && key.chars().all(|c| c.is_ascii_hexdigit())
}

#[cfg(test)]
mod tests {
    use super::*;

    const ENTRY: &str = "ball-0123456789abcdef.patches";

    #[test]
    fn only_listed_entries_of_a_tagged_folder_go() {
        let dir = tempfile::tempdir().unwrap();
        let cache = dir.path().join("cache");
        make(&cache).unwrap();
        std::fs::write(cache.join(ENTRY), b"store").unwrap();
        record(&cache, ENTRY).unwrap();
        let mine = "survey-2024010112304500.patches";
        std::fs::write(cache.join(mine), b"the user's").unwrap();
        assert_eq!(clean_cache(&cache).unwrap(), (1, 5));
        assert!(cache.join(mine).exists() && !cache.join(ENTRY).exists());
        std::fs::remove_file(cache.join(mine)).unwrap();
        assert_eq!(clean_cache(&cache).unwrap(), (0, 0));
        assert!(!cache.exists(), "an emptied cache folder goes, with its bookkeeping");
    }

    #[test]
    fn another_programs_tag_is_kept_and_only_the_listed_entries_go() {
        let dir = tempfile::tempdir().unwrap();
        let theirs = "Signature: 8a477f597d28d172789f06886806bc55\n# cargo\n";
        std::fs::write(dir.path().join(TAG_NAME), theirs).unwrap();
        make(dir.path()).unwrap();
        assert_eq!(std::fs::read_to_string(dir.path().join(TAG_NAME)).unwrap(), theirs);
        assert!(clean_cache(dir.path()).is_err(), "no list: nothing the cache wrote");
        std::fs::write(dir.path().join(ENTRY), b"store").unwrap();
        record(dir.path(), ENTRY).unwrap();
        assert_eq!(clean_cache(dir.path()).unwrap(), (1, 5));
        assert_eq!(std::fs::read_to_string(dir.path().join(TAG_NAME)).unwrap(), theirs);
    }

    #[test]
    fn an_untagged_default_folder_is_a_cache_from_before_the_tag() {
        let dir = tempfile::tempdir().unwrap();
        let cache = dir.path().join(DEFAULT_NAME);
        std::fs::create_dir(&cache).unwrap();
        std::fs::write(cache.join(ENTRY), b"store").unwrap();
        assert_eq!(clean_cache(&cache).unwrap(), (1, 5));
        assert!(!cache.exists());
    }
}
