//! Inputs must be files; outputs must spare every input, and be files in folders that exist.

use std::path::PathBuf;

use pointray_io::formats::read_point_cloud;
use pointray_io::{IoError, ensure_outputs_spare_inputs, ensure_readable_file, ensure_writable_output};

#[test]
fn folders_and_devices_are_named_as_such_not_as_missing() {
    let dir = tempfile::tempdir().unwrap();
    let folder = read_point_cloud(dir.path()).unwrap_err().to_string();
    assert!(folder.contains("is a folder, not a file"), "{folder}");
    let missing = ensure_readable_file(&dir.path().join("gone.ply")).unwrap_err().to_string();
    assert!(missing.contains("gone.ply: file not found"), "{missing}");
    #[cfg(unix)]
    {
        let device = read_point_cloud(std::path::Path::new("/dev/zero")).unwrap_err().to_string();
        assert!(device.contains("is a device, not a file"), "{device}");
    }
}

#[test]
fn outputs_must_be_files_in_existing_folders() {
    let dir = tempfile::tempdir().unwrap();
    ensure_writable_output(&dir.path().join("new.png")).unwrap();
    let into_folder = ensure_writable_output(dir.path()).unwrap_err().to_string();
    assert!(into_folder.contains("is a folder; an output must be a file"), "{into_folder}");
    let missing = ensure_writable_output(&dir.path().join("typo/out.png")).unwrap_err().to_string();
    assert!(missing.contains("does not exist") && missing.contains("typo"), "{missing}");
    #[cfg(unix)]
    {
        let device = ensure_writable_output(std::path::Path::new("/dev/null")).unwrap_err();
        assert!(matches!(device, IoError::Unusable { .. }), "{device}");
    }
}

#[test]
fn every_output_is_checked_against_every_existing_input() {
    let dir = tempfile::tempdir().unwrap();
    let [scene, points, absent]: [PathBuf; 3] =
        ["scene.toml", "points.ply", "absent.ply"].map(|n| dir.path().join(n));
    std::fs::write(&scene, b"scene").unwrap();
    std::fs::write(&points, b"points").unwrap();
    let inputs = vec![scene.clone(), points.clone(), absent.clone()];
    ensure_outputs_spare_inputs(&inputs, &[dir.path().join("out.png"), absent]).unwrap();
    #[cfg(unix)]
    {
        let link = dir.path().join("out.depth.exr");
        std::os::unix::fs::symlink(&points, &link).unwrap();
        let error = ensure_outputs_spare_inputs(&inputs, &[dir.path().join("out.png"), link]).unwrap_err();
        assert!(matches!(error, IoError::SameFile { .. }), "{error}");
    }
    let error = ensure_outputs_spare_inputs(&inputs, &[scene]).unwrap_err();
    assert!(error.to_string().contains("refusing to write over the input"), "{error}");
    assert_eq!(std::fs::read(&points).unwrap(), b"points");
}

/// Two outputs that name one file (`bench --json r.json --markdown r.json`, or through a link)
/// would overwrite each other; an output ending in a separator (`-o out.png/`) can only fail
/// after the work. Both are refused before it.
#[test]
fn outputs_must_differ_and_not_end_in_a_separator() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("r.json");
    let same = dir.path().join(".").join("r.json");
    let error = ensure_outputs_spare_inputs(&[], &[report.clone(), same]).unwrap_err().to_string();
    assert!(error.contains("r.json") && error.contains("is also the output"), "{error}");
    #[cfg(unix)]
    {
        std::fs::write(&report, b"{}").unwrap();
        let link = dir.path().join("link.json");
        std::os::unix::fs::symlink(&report, &link).unwrap();
        assert!(ensure_outputs_spare_inputs(&[], &[report.clone(), link]).is_err());
    }
    ensure_outputs_spare_inputs(&[], &[report, dir.path().join("r.md")]).unwrap();
    let slash = PathBuf::from(format!("{}/out.png/", dir.path().display()));
    let error = ensure_writable_output(&slash).unwrap_err().to_string();
    assert!(error.contains("out.png/") && error.contains("separator"), "{error}");
}
