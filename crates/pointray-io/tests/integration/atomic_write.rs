//! Atomic writes: all or nothing, no temporary files left behind, inputs protected.

use std::io::Write;

use pointray_io::{IoError, ensure_not_same_file, write_atomically};

#[test]
fn a_successful_write_replaces_the_file_and_leaves_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.txt");
    std::fs::write(&path, b"old contents").unwrap();
    write_atomically(&path, |out| out.write_all(b"new")).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"new");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn a_failed_write_keeps_the_old_file_and_removes_the_temporary() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.txt");
    std::fs::write(&path, b"old contents").unwrap();
    let error = write_atomically(&path, |out| {
        out.write_all(b"half of it")?;
        Err(std::io::Error::other("disk on fire"))
    })
    .unwrap_err();
    assert!(error.to_string().contains("out.txt") && error.to_string().contains("disk on fire"), "{error}");
    assert_eq!(std::fs::read(&path).unwrap(), b"old contents");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn a_missing_directory_is_an_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("no/such/dir/out.txt");
    let error = write_atomically(&path, |out| out.write_all(b"x")).unwrap_err();
    assert!(matches!(error, IoError::Os { .. }) && error.to_string().contains("out.txt"), "{error}");
}

#[cfg(unix)]
#[test]
fn written_files_are_readable_by_others_like_ordinary_outputs() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.txt");
    write_atomically(&path, |out| out.write_all(b"x")).unwrap();
    // An ordinary file gets 0666 less the umask; ours gets 0644 less the umask, not 0600.
    let reference = dir.path().join("reference.txt");
    std::fs::write(&reference, b"x").unwrap();
    let mode = |p: &std::path::Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&path), mode(&reference) & 0o644);
}

#[test]
fn the_input_cannot_be_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ply");
    std::fs::write(&input, b"data").unwrap();
    let same = dir.path().join(".").join("in.ply");
    assert!(matches!(ensure_not_same_file(&input, &same), Err(IoError::SameFile { .. })));
    let other = dir.path().join("out.ply");
    ensure_not_same_file(&input, &other).unwrap();
    std::fs::write(&other, b"old").unwrap();
    ensure_not_same_file(&input, &other).unwrap();
}

#[cfg(unix)]
#[test]
fn links_to_the_input_are_recognised() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.ply");
    std::fs::write(&input, b"data").unwrap();
    let symlink = dir.path().join("alias.ply");
    std::os::unix::fs::symlink(&input, &symlink).unwrap();
    let hard_link = dir.path().join("hard.ply");
    std::fs::hard_link(&input, &hard_link).unwrap();
    for output in [symlink, hard_link] {
        let error = ensure_not_same_file(&input, &output).unwrap_err().to_string();
        assert!(error.contains("refusing to write over the input"), "{error}");
    }
}

#[cfg(target_os = "linux")]
#[test]
fn temporaries_whose_writers_are_gone_are_removed_and_live_ones_kept() {
    let dir = tempfile::tempdir().unwrap();
    // Above Linux's largest process id (2^22), so no process here can have it. These names carry
    // no kernel tag, so their writers might run on another host: only their locks and ages tell.
    let gone = dir.path().join(".pointray-4194305-AbCdEf.tmp");
    let locked = dir.path().join(".pointray-4194305-MnOpQr.tmp");
    let fresh = dir.path().join(".pointray-4194305-StUvWx.tmp");
    let foreign = dir.path().join(".tmpXyZ123");
    for path in [&gone, &locked, &fresh, &foreign] {
        std::fs::write(path, b"partial").unwrap();
    }
    for path in [&gone, &locked, &foreign] {
        let two_days = std::time::Duration::from_secs(2 * 24 * 60 * 60);
        let file = std::fs::File::options().write(true).open(path).unwrap();
        file.set_modified(std::time::SystemTime::now() - two_days).unwrap();
    }
    // A live writer in another PID namespace or on another host holds its temporary's lock.
    let writer = std::fs::File::open(&locked).unwrap();
    writer.lock_shared().unwrap();
    write_atomically(&dir.path().join("out.txt"), |out| out.write_all(b"x")).unwrap();
    assert!(!gone.exists(), "a temporary whose lock is free and which lay untouched for a day goes");
    assert!(locked.exists() && fresh.exists(), "a held lock, or a recent write, keeps a temporary");
    assert!(foreign.exists(), "other programs' files stay");
}
