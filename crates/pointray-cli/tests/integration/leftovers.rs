//! What runs leave behind: SIGTERM and SIGINT end a command through its handler, which removes
//! any temporary file of a write in progress (`pointray_io::temporaries`), and stale ones of
//! killed runs go with the next write into their folder, never those of a run in another PID
//! namespace; warnings piped to a file carry no colour codes; `pointray cache clean` empties
//! the point-set cache.

use crate::common::{cached_store, pointray_in, write_grid_ply};

#[cfg(target_os = "linux")]
#[test]
fn sigterm_ends_prep_through_the_cleanup_handler() {
    use std::process::{Command, Stdio};

    let dir = tempfile::tempdir().unwrap();
    // Large enough that prep is still running when the signal comes.
    let mut text = String::from(
        "ply\nformat ascii 1.0\nelement vertex 250000\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
    );
    for i in 0..250_000 {
        let (x, z) = ((i % 500) as f32 * 0.01, (i / 500) as f32 * 0.01);
        text += &format!("{x} {} {z}\n", (x * 3.0).sin() * 0.1);
    }
    std::fs::write(dir.path().join("big.ply"), text).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_pointray"))
        .current_dir(dir.path())
        .args(["prep", "big.ply", "-o", "big.patches"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // Signal only once the handler catches SIGTERM (bit 14 of the caught-signal mask).
    let status_file = format!("/proc/{}/status", child.id());
    let catches_sigterm = || {
        let status = std::fs::read_to_string(&status_file).unwrap_or_default();
        let mask = status.lines().find_map(|line| line.strip_prefix("SigCgt:")).unwrap_or("0");
        u64::from_str_radix(mask.trim(), 16).is_ok_and(|mask| mask & (1 << 14) != 0)
    };
    while !catches_sigterm() {
        assert!(child.try_wait().unwrap().is_none(), "prep ended before its handler was seen");
        std::thread::yield_now();
    }
    Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "the handler ends the process: {status}");
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().flatten().map(|e| e.file_name()).collect();
    assert_eq!(left, vec![std::ffi::OsString::from("big.ply")], "nothing but the input is left");
}

/// A wavy sheet of `count` points as an ASCII PLY, large enough that prep is still running a
/// moment after it starts.
fn write_big_ply(path: &std::path::Path, count: usize) {
    let mut text = format!(
        "ply\nformat ascii 1.0\nelement vertex {count}\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
    );
    for i in 0..count {
        let (x, z) = ((i % 500) as f32 * 0.01, (i / 500) as f32 * 0.01);
        text += &format!("{x} {} {z}\n", (x * 3.0).sin() * 0.1);
    }
    std::fs::write(path, text).unwrap();
}

/// Two preps in one folder from two PID namespaces (two containers, or the README's Slurm
/// jobs): to the second, the first's process id names no running process, yet it does not
/// remove the first's temporaries, which the first holds locked.
#[cfg(target_os = "linux")]
#[test]
fn preps_in_two_pid_namespaces_share_one_folder() {
    use std::process::{Command, Stdio};

    let pointray = || Command::new(env!("CARGO_BIN_EXE_pointray"));
    // In a PID namespace of its own, where only it runs: every other process id is free.
    let in_namespace = |args: &[&str]| {
        let mut command = Command::new("unshare");
        command.args(["--user", "--map-root-user", "--pid", "--fork", "--mount-proc"]);
        command.arg(env!("CARGO_BIN_EXE_pointray")).args(args);
        command
    };
    let probe = in_namespace(&["--version"]).stdout(Stdio::null()).stderr(Stdio::null()).status();
    if !probe.is_ok_and(|status| status.success()) {
        eprintln!("skipped: this machine gives no user and PID namespaces (unshare failed)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    write_big_ply(&dir.path().join("big.ply"), 100_000);
    write_grid_ply(&dir.path().join("grid.ply"));
    let mut first = pointray()
        .args(["prep", "big.ply", "-o", "a.patches", "--tiles", "4"])
        .current_dir(dir.path())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let temporary_exists = || {
        let names = std::fs::read_dir(dir.path()).unwrap().flatten().map(|e| e.file_name());
        names.map(|name| name.to_string_lossy().into_owned()).any(|name| name.ends_with(".tmp"))
    };
    while !temporary_exists() {
        assert!(first.try_wait().unwrap().is_none(), "the first prep ended before its temporaries were seen");
        std::thread::yield_now();
    }
    let second =
        in_namespace(&["prep", "grid.ply", "-o", "b.patches"]).current_dir(dir.path()).output().unwrap();
    assert!(second.status.success(), "{}", String::from_utf8_lossy(&second.stderr));
    assert!(first.try_wait().unwrap().is_none(), "the first prep still ran while the second swept");
    let first = first.wait_with_output().unwrap();
    assert!(first.status.success(), "{}", String::from_utf8_lossy(&first.stderr));
    assert!(dir.path().join("a.patches").is_file() && dir.path().join("b.patches").is_file());
}

/// A reader that stops reading (`| head`) ends the command by SIGPIPE, as it ends other Unix
/// tools: no panic message, and the image written before the line is whole.
#[cfg(target_os = "linux")]
#[test]
fn a_closed_output_pipe_ends_render_without_a_panic() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::{Command, Stdio};

    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_pointray"))
        .current_dir(dir.path())
        .args(["render", "grid.ply", "-o", "out.png", "--backend", "cpu", "--width", "8", "--height", "8"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The reader goes before the command's first line: reading and prepping the grid take longer.
    drop(child.stdout.take());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(output.status.signal(), Some(libc::SIGPIPE), "{}: {stderr}", output.status);
}

#[test]
fn warnings_carry_no_colour_codes_when_piped() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    std::fs::write(dir.path().join("grid.patches"), b"PRPATCH\0 not really").unwrap();
    std::fs::write(dir.path().join("scene.toml"), "[[objects]]\ntype = \"points\"\npath = \"grid.ply\"\n")
        .unwrap();
    let args = ["render", "scene.toml", "-o", "out.png", "--backend", "cpu", "--width", "8", "--height", "8"];
    assert!(pointray_in(dir.path(), &args).0);
    let cache = cached_store(dir.path());
    std::fs::write(&cache, b"PRPATCH\0 damaged").unwrap();
    let (ok, _, stderr) = pointray_in(dir.path(), &args);
    assert!(ok && stderr.contains("regenerating"), "a warning is printed: {stderr}");
    assert!(!stderr.contains('\u{1b}'), "no ANSI escape codes: {stderr:?}");
}

#[test]
fn cache_clean_removes_cached_point_sets_and_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    crate::common::write_points_scene(dir.path(), "scene.toml", "grid.ply");
    let args = ["render", "scene.toml", "-o", "out.png", "--backend", "cpu", "--width", "8", "--height", "8"];
    assert!(pointray_in(dir.path(), &args).0);
    let cache = dir.path().join(".pointray-cache");
    std::fs::write(cache.join("notes.txt"), b"mine").unwrap();
    let (ok, stdout, stderr) = pointray_in(dir.path(), &["cache", "clean"]);
    assert!(ok && stdout.contains("removed 1 cached point sets"), "{stdout}{stderr}");
    let mut left: Vec<_> = std::fs::read_dir(&cache).unwrap().flatten().map(|e| e.file_name()).collect();
    left.sort();
    assert_eq!(
        left,
        ["CACHEDIR.TAG", "notes.txt"].map(std::ffi::OsString::from),
        "the tag stays with notes.txt"
    );
    std::fs::remove_file(cache.join("notes.txt")).unwrap();
    assert!(pointray_in(dir.path(), &args).0);
    assert!(pointray_in(dir.path(), &["cache", "clean"]).0);
    assert!(!cache.exists(), "an emptied cache folder goes too");
}

/// `cache clean DIR` on a folder the cache never made removes nothing, not even files named
/// as cache entries are (`survey-2024010112304500.patches`), and keeps the folder.
#[test]
fn cache_clean_leaves_a_folder_the_cache_did_not_make() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("surveys");
    std::fs::create_dir(&folder).unwrap();
    let survey = folder.join("survey-2024010112304500.patches");
    std::fs::write(&survey, b"PRPATCH\0 the user's own store").unwrap();
    let (ok, _, stderr) = pointray_in(dir.path(), &["cache", "clean", "surveys"]);
    assert!(!ok && stderr.contains("surveys") && stderr.contains("not a pointray cache"), "{stderr}");
    assert!(survey.exists(), "the user's file stays");
    std::fs::remove_file(&survey).unwrap();
    assert!(!pointray_in(dir.path(), &["cache", "clean", "surveys"]).0);
    assert!(folder.is_dir(), "an empty folder the cache did not make stays too");
}

/// Output that cannot be written (a full disk; `> /dev/full`) is an error like any other, not
/// a panic: exit status 1 and one line saying so.
#[cfg(target_os = "linux")]
#[test]
fn a_full_stdout_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    let render = ["render", "grid.ply", "-o", "out.exr", "--backend", "cpu", "--width", "8", "--height", "8"];
    assert!(pointray_in(dir.path(), &render).0, "the image compare reads");
    let commands: [&[&str]; 3] =
        [&["prep", "grid.ply", "-o", "grid.patches"], &render, &["compare", "out.exr", "out.exr"]];
    for args in commands {
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_pointray"))
            .current_dir(dir.path())
            .args(args)
            .stdout(std::fs::File::options().write(true).open("/dev/full").unwrap())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains("stdout") && !stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}
