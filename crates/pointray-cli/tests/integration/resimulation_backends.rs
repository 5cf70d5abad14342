//! `scan --rays-from` on either backend: a real Ouster OS-1-128 sweep
//! (data/scans/real/ouster_os1_128_seq/, data/SOURCES.md) re-simulated in its own map by the
//! Vulkan ray list (lavapipe where there is no GPU) and by the CPU, which must report the same
//! comparison with the real sweep.

use std::path::Path;

use pointray_test_support::{data_file, skip_without_device};

use crate::common::pointray_in;

/// The re-simulation's report on `backend`, or `None` when the Vulkan backend found no device.
fn report_on(dir: &Path, map: &Path, backend: &str) -> Option<serde_json::Value> {
    let sweep = data_file("scans/real/ouster_os1_128_seq/scan00.bin");
    let json = dir.join(format!("{backend}.json"));
    let output = dir.join(format!("{backend}.bin"));
    let args = [
        "scan",
        map.to_str().unwrap(),
        "--rays-from",
        sweep.to_str().unwrap(),
        "--pose",
        "1 0 0 0 0 1 0 0 0 0 1 0",
        "--backend",
        backend,
        "-o",
        output.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ];
    let (ok, stdout, stderr) = pointray_in(dir, &args);
    if !ok && stderr.contains("no Vulkan device opened") {
        skip_without_device(&stderr);
        return None;
    }
    assert!(ok, "pointray {args:?} failed:\n{stdout}\n{stderr}");
    assert!(stdout.contains(&format!("backend: {backend}")), "{stdout}");
    Some(serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap())
}

#[test]
fn a_sweep_re_simulated_on_vulkan_reports_what_the_cpu_reports() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = data_file("scans/real/ouster_os1_128_seq/scan00.bin");
    let map = dir.path().join("map.patches");
    let (ok, stdout, stderr) =
        pointray_in(dir.path(), &["prep", sweep.to_str().unwrap(), "-o", map.to_str().unwrap()]);
    assert!(ok, "prep failed:\n{stdout}\n{stderr}");
    let Some(vulkan) = report_on(dir.path(), &map, "vulkan") else { return };
    let cpu = report_on(dir.path(), &map, "cpu").expect("the CPU backend needs no device");
    let number = |report: &serde_json::Value, field: &str| report[field].as_f64().unwrap();
    for field in ["agreeing_fraction", "chamfer", "median_abs_range_error"] {
        let (on_vulkan, on_cpu) = (number(&vulkan, field), number(&cpu, field));
        // A ray or two may meet either of two overlapping patches first on the two backends.
        assert!(
            (on_vulkan - on_cpu).abs() <= 1e-4 * on_cpu.abs().max(1.0),
            "{field}: {on_vulkan} against {on_cpu}"
        );
    }
    assert!(number(&cpu, "agreeing_fraction") > 0.95, "the sweep agrees with its own map: {cpu:#}");
}
