//! What the CLI tests share.

use std::path::{Path, PathBuf};

/// Runs the `pointray` binary in `dir`: (success, stdout, stderr).
pub fn pointray_in(dir: &Path, args: &[&str]) -> (bool, String, String) {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_pointray"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("pointray runs");
    let text = |bytes: &[u8]| String::from_utf8_lossy(bytes).into_owned();
    (output.status.success(), text(&output.stdout), text(&output.stderr))
}

/// A wavy 20x20 grid of points as an ASCII PLY: enough for prep, quick to render.
pub fn write_grid_ply(path: &Path) {
    let mut text = String::from(
        "ply\nformat ascii 1.0\nelement vertex 400\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
    );
    for i in 0..400 {
        let (x, z) = ((i % 20) as f32 * 0.05, (i / 20) as f32 * 0.05);
        text += &format!("{x} {} {z}\n", 0.02 * (x * 7.0).sin());
    }
    std::fs::write(path, text).unwrap();
}

/// A scene in `dir` named `name` that shows the points file `points` (relative to `dir`) on
/// an automatic ground, lit by one light.
pub fn write_points_scene(dir: &Path, name: &str, points: &str) -> PathBuf {
    let path = dir.join(name);
    let text = format!(
        "[[lights]]\ntype = \"point\"\nposition = [0.5, 2.0, 1.5]\n\n[[objects]]\ntype = \"points\"\npath = \"{points}\"\n\n\
         [[objects]]\ntype = \"ground\"\nauto = true\n"
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// The one prepped store in `dir`'s cache folder, beside the folder's own files.
pub fn cached_store(dir: &Path) -> PathBuf {
    let entries = std::fs::read_dir(dir.join(".pointray-cache")).unwrap();
    entries
        .map(|entry| entry.unwrap().path())
        .find(|path| path.extension().is_some_and(|extension| extension == "patches"))
        .expect("a cached store")
}
