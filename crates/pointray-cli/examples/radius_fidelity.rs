//! The measurement behind `bench/FIDELITY.md`, "Radius modes on uneven density" and "Disk
//! scale": the paper's support radius against the adaptive one, each at disk scale 1 and 0.7,
//! on mesh samples thinned by a tenfold density gradient and into scan lines, compared with
//! the mesh by `pointray-fidelity`.
//!
//! `pointray fidelity` preps with the default radius and has no radius flag, so this drives
//! the same library calls. It prints a markdown table and takes minutes:
//!
//! ```sh
//! cargo run --release -p pointray-cli --example radius_fidelity
//! ```
//! `POINTRAY_FIDELITY_SIZE` sets the image size (default 512, as `pointray fidelity`).

use pointray_test_support::data_file;

use std::sync::Arc;

use pointray_fidelity::{CpuImageRenderer, FidelityMetrics, FidelityOptions, measure_fidelity};
use pointray_io::PointCloud;
use pointray_patches::{PrepSettings, RadiusMode};
use pointray_scene::PatchAcceptance;
use pointray_surface::uneven_sampling::{Unevenness, sample_mesh_unevenly};
use pointray_surface::{NoProgress, prep};

const MODELS: [&str; 3] = ["bunny", "horse", "dragon_res2"];
const SAMPLES: usize = 40_000;
const DISK_SCALES: [f32; 2] = [1.0, 0.7];
const SAMPLINGS: [(&str, Unevenness); 3] = [
    ("uniform", Unevenness::Gradient { ratio: 1.0 }),
    ("gradient 10x", Unevenness::Gradient { ratio: 10.0 }),
    ("scan lines 60 x 25%", Unevenness::ScanLines { lines: 60, duty: 0.25 }),
];

fn measure(
    cloud: &PointCloud,
    mesh: &Arc<pointray_io::TriangleMesh>,
    mode: RadiusMode,
    disk_scale: f32,
    size: u32,
) -> FidelityMetrics {
    let mut options = PrepSettings { radius: mode, ..PrepSettings::default() };
    options.disk_scale = disk_scale;
    let (patches, _) = prep(cloud, &options, &NoProgress).expect("the samples prep");
    let fidelity = FidelityOptions::around(6, size, PatchAcceptance::Disk).unwrap();
    measure_fidelity(Arc::new(patches), mesh.clone(), &fidelity, &CpuImageRenderer).unwrap().overall
}

fn row(
    model: &str,
    sampling: &str,
    points: usize,
    (mode, scale): (RadiusMode, f32),
    m: &FidelityMetrics,
) -> String {
    let f = |value: Option<f64>, scale: f64| value.map_or("-".into(), |v| format!("{:.4}", v * scale));
    format!(
        "| {model} | {sampling} | {points} | {mode:?} | {scale} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
        f(m.hole_rate.map(|r| r * m.mesh_pixels as f64), 1.0).trim_end_matches(".0000"),
        f(m.pinhole_rate.map(|r| r * m.mesh_pixels as f64), 1.0).trim_end_matches(".0000"),
        f(m.hole_rate, 100.0),
        f(m.false_surface_rate, 100.0),
        f(m.depth_error_mean, 1.0),
        f(m.depth_error_p99, 1.0),
        f(m.normal_error_mean_degrees, 1.0),
        f(m.normal_error_p95_degrees, 1.0),
        f(m.psnr_db, 1.0),
    )
}

fn main() {
    let size = std::env::var("POINTRAY_FIDELITY_SIZE").ok().and_then(|s| s.parse().ok()).unwrap_or(512);
    println!(
        "| model | sampling | points | radius | disk scale | hole px | pinhole px | hole % | false surface % | depth mean | depth p99 | normal mean ° | normal p95 ° | PSNR dB |"
    );
    println!("|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for model in MODELS {
        let path = data_file(&format!("meshes/{model}.ply"));
        let mesh = Arc::new(pointray_io::formats::read_triangle_mesh(&path).unwrap());
        for (sampling, unevenness) in SAMPLINGS {
            let cloud = sample_mesh_unevenly(&mesh, SAMPLES, 1, unevenness);
            for mode in [RadiusMode::Paper, RadiusMode::Adaptive, RadiusMode::Cell] {
                for scale in DISK_SCALES {
                    let metrics = measure(&cloud, &mesh, mode, scale, size);
                    println!("{}", row(model, sampling, cloud.len(), (mode, scale), &metrics));
                }
            }
        }
    }
}
