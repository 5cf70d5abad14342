//! `--columns`: every command that reads points takes it; a raw sweep its name does not
//! explain is refused without it, naming the file, and read with it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn pointray(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pointray")).args(args).output().expect("pointray runs")
}

/// A nuScenes-like sweep of a 30x30 patch of road 1.8 m below the sensor, 5 floats a point,
/// under a KITTI-like name.
fn write_sweep(dir: &Path) -> PathBuf {
    let bytes: Vec<u8> = (0..900)
        .flat_map(|i| [(i % 30) as f32 * 0.1, (i / 30) as f32 * 0.1, -1.8, 0.5, (i % 32) as f32])
        .flat_map(f32::to_le_bytes)
        .collect();
    let path = dir.join("000042.bin");
    std::fs::write(&path, bytes).unwrap();
    path
}

fn output_text(output: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr))
}

#[test]
fn prep_reads_a_sweep_with_columns_and_refuses_it_without() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = write_sweep(dir.path());
    let store = dir.path().join("sweep.patches");
    let args = ["prep", sweep.to_str().unwrap(), "-o", store.to_str().unwrap()];
    let refused = pointray(&args);
    let text = output_text(&refused);
    assert!(!refused.status.success() && text.contains("000042.bin") && text.contains("--columns"), "{text}");
    assert!(!store.exists());

    let read = pointray(&[&args[..], &["--columns", "x,y,z,intensity,ring"]].concat());
    assert!(read.status.success(), "{}", output_text(&read));
    assert_eq!(pointray_patches::patch_store::read(&store).unwrap().len(), 900);
}

#[test]
fn render_passes_columns_to_the_scene_and_bad_names_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = write_sweep(dir.path());
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, format!("[[objects]]\ntype = \"points\"\npath = \"{}\"\n", sweep.display()))
        .unwrap();
    let image = dir.path().join("out.png");
    let args =
        ["render", scene.to_str().unwrap(), "-o", image.to_str().unwrap(), "--width", "32", "--height", "32"];
    let refused = pointray(&[&args[..], &["--backend", "cpu"]].concat());
    assert!(!refused.status.success() && output_text(&refused).contains("000042.bin"));

    let rendered =
        pointray(&[&args[..], &["--backend", "cpu", "--columns", "x,y,z,intensity,ring"]].concat());
    assert!(rendered.status.success(), "{}", output_text(&rendered));
    assert!(image.is_file());

    let bad = pointray(&[&args[..], &["--columns", "x,y,w"]].concat());
    assert!(!bad.status.success() && output_text(&bad).contains("unknown column name \"w\""));
}

#[test]
fn every_command_that_reads_points_offers_columns() {
    for command in ["prep", "render", "view", "fidelity"] {
        let help = output_text(&pointray(&[command, "--help"]));
        assert!(help.contains("--columns <NAMES>"), "{command}: {help}");
    }
}
