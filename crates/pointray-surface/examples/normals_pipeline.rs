//! Times the first `prep` stages (Morton order, duplicate merge, kNN, PCA normals,
//! orientation) on points sampled from a mesh, and measures how many oriented normals
//! agree in sign with the face each point was sampled from.
//!
//! `cargo run --release -p pointray-surface --example normals_pipeline -- [MESH] [COUNT] [SEED]`
//! (defaults: `dragon_res2.ply` from the test data, 1,000,000 points, seed 1).
//!
//! It has its own sampler because `sampling::sample_mesh` does not say which triangle each
//! point came from, and that triangle's normal is the reference here.
//!
//! Measured 2026-11-21, 1,000,000 points from `dragon_res2.ply`, seed 1, release build,
//! 2 rayon threads (wall ms; sign agreement 99.69% of 1,000,000, unoriented 50.71%):
//!
//! | stage | 2 cores of an idle 16-core host (`taskset -c 0,1`), fastest of 3 runs | the 2-core dev VM, load average ~7 |
//! |---|---|---|
//! | morton order | 41 | 70 |
//! | apply order | 13 | 17 |
//! | merge duplicates | 163 | 206 |
//! | k nearest (k = 16) | 867 | 1814 |
//! | pca normals | 330 | 1024 |
//! | orientation | 382 (2.6 M points/s) | 831 (1.2 M points/s) |
//! | total | 1801 (the 3 totals: 1906, 1850, 1801) | 3969 |

#[allow(dead_code)] // the example needs only a few of the tests' helpers
#[path = "../tests/integration/normals_support/mod.rs"]
mod normals_support;

use std::path::PathBuf;
use std::time::Instant;

use glam::{DVec3, Vec3};
use normals_support::{FIT_K, NORMAL_K, sign_agreement};
use pointray_io::TriangleMesh;
use pointray_io::formats::ply::read_triangle_mesh;
use pointray_patches::PrepSettings;
use pointray_surface::duplicates::merge_duplicates;
use pointray_surface::morton::morton_order;
use pointray_surface::neighbors::k_nearest;
use pointray_surface::normals::pca_normals;
use pointray_surface::orientation::orient_consistently;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let mesh_path = match args.next() {
        Some(path) => PathBuf::from(path),
        None => pointray_test_support::data_file("meshes/dragon_res2.ply"),
    };
    let count: usize = args.next().map_or(Ok(1_000_000), |a| a.parse())?;
    let seed: u64 = args.next().map_or(Ok(1), |a| a.parse())?;

    let mesh = read_triangle_mesh(&mesh_path)?;
    let (points, triangles) = sample_with_triangles(&mesh, count, seed);
    println!(
        "{count} points from {} (seed {seed}), {} threads",
        mesh_path.display(),
        rayon::current_num_threads()
    );

    let mut stages = Stages::default();
    let order = stages.time("morton order", || morton_order(&points));
    let (points, triangles) = stages.time("apply order", || {
        let sorted: Vec<Vec3> = order.iter().map(|&i| points[i as usize]).collect();
        let sorted_triangles: Vec<u32> = order.iter().map(|&i| triangles[i as usize]).collect();
        (sorted, sorted_triangles)
    });
    // `prep`'s duplicate tolerance, in f32 ulps at each point's coordinates.
    let tolerance = PrepSettings::default().duplicate_tolerance;
    let merge = stages.time("merge duplicates", || merge_duplicates(&points, tolerance));
    let (points, triangles) = stages.time("apply merge", || {
        let kept_points: Vec<Vec3> = merge.kept.iter().map(|&i| points[i as usize]).collect();
        let kept_triangles: Vec<u32> = merge.kept.iter().map(|&i| triangles[i as usize]).collect();
        (kept_points, kept_triangles)
    });
    println!("merged {} duplicates (tolerance {tolerance} ulps)", merge.merged_count);
    let neighbors = stages.time("k nearest (k = 16)", || k_nearest(&points, FIT_K.max(NORMAL_K)));
    let mut normals = stages.time("pca normals", || pca_normals(&points, &neighbors, NORMAL_K));
    let face_normals: Vec<Vec3> = triangles.iter().map(|&t| mesh.face_normal(t as usize)).collect();
    let (unoriented_rate, _) = sign_agreement(&normals, &face_normals);
    let orientation_seconds =
        stages.time_seconds("orientation", || orient_consistently(&points, &mut normals, &neighbors));
    stages.print();

    let (rate, compared) = sign_agreement(&normals, &face_normals);
    println!(
        "orientation: {:.2} M points/s; sign agreement with the sampled faces {:.4}% of {compared} \
         (unoriented PCA normals: {:.2}%)",
        points.len() as f64 / orientation_seconds / 1e6,
        rate * 100.0,
        unoriented_rate * 100.0
    );
    Ok(())
}

/// Wall times of the stages, in the order they ran.
#[derive(Default)]
struct Stages(Vec<(&'static str, f64)>);

impl Stages {
    fn time<T>(&mut self, name: &'static str, stage: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let result = stage();
        self.0.push((name, start.elapsed().as_secs_f64()));
        result
    }

    fn time_seconds(&mut self, name: &'static str, stage: impl FnOnce()) -> f64 {
        self.time(name, stage);
        self.0.last().map_or(0.0, |&(_, seconds)| seconds)
    }

    fn print(&self) {
        for (name, seconds) in &self.0 {
            println!("{name:>20}: {:8.1} ms", seconds * 1e3);
        }
        let total: f64 = self.0.iter().map(|(_, s)| s).sum();
        println!("{:>20}: {:8.1} ms", "total", total * 1e3);
    }
}

/// Uniform area-weighted samples, each with the index of the triangle it lies on.
fn sample_with_triangles(mesh: &TriangleMesh, count: usize, seed: u64) -> (Vec<Vec3>, Vec<u32>) {
    let corners = |t: usize| mesh.triangles[t].map(|v| mesh.positions[v as usize].as_dvec3());
    let mut total = 0.0;
    let running: Vec<f64> = (0..mesh.triangles.len())
        .map(|t| {
            let [a, b, c] = corners(t);
            total += 0.5 * (b - a).cross(c - a).length();
            total
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|_| {
            let target = rng.random::<f64>() * total;
            let t = running.partition_point(|&sum| sum <= target).min(running.len() - 1);
            let [a, b, c] = corners(t);
            // sqrt warps the first coordinate so that the density is uniform over the area.
            let (s, u) = (rng.random::<f64>().sqrt(), rng.random::<f64>());
            let p: DVec3 = a * (1.0 - s) + b * (s * (1.0 - u)) + c * (s * u);
            (p.as_vec3(), t as u32)
        })
        .unzip()
}
