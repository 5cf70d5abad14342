//! Read throughput of a COPC file: its chunks found through its hierarchy and decoded in
//! parallel (`read_las`, as pointray reads COPC), against the same file read as plain LAZ
//! through the `las` crate's reader (`read_las_from` on a stream), which decompresses the
//! chunks its chunk table lists in parallel too. A measurement: it checks only that both give the same cloud, and prints a
//! markdown table of points/s. There is no COPC writer among the crates here, so it takes an
//! existing file (`data/scans/write_autzen_copc.py` writes one with copclib):
//!
//! ```sh
//! cargo run --release -p pointray-io --example copc_throughput -- FILE.copc.laz
//! ```

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::time::Instant;

use pointray_io::PointCloud;
use pointray_io::formats::las::{read_las, read_las_from};

const RUNS: usize = 3;

/// The best wall time of `RUNS` reads, and the cloud read.
fn best_of(read: impl Fn() -> PointCloud) -> (f64, PointCloud) {
    let mut cloud = PointCloud::default();
    let mut best = f64::INFINITY;
    for _ in 0..RUNS {
        let start = Instant::now();
        cloud = read();
        best = best.min(start.elapsed().as_secs_f64());
    }
    (best, cloud)
}

fn row(name: &str, seconds: f64, points: usize) {
    println!("| {name} | {points} | {seconds:.3} s | {:.2} M points/s |", points as f64 / seconds / 1e6);
}

fn main() {
    let Some(path) = std::env::args_os().nth(1).map(PathBuf::from) else {
        eprintln!("usage: copc_throughput FILE.copc.laz");
        std::process::exit(2);
    };
    let as_laz = |path: &Path| {
        let stream = BufReader::new(File::open(path).expect("the file opens"));
        read_las_from(stream, path).expect("the file reads as LAZ")
    };
    let (parallel_seconds, parallel) = best_of(|| read_las(&path).expect("the file reads as COPC"));
    let (laz_seconds, laz) = best_of(|| as_laz(&path));
    assert!(parallel == laz, "both reads give the same cloud");
    println!("{}: {} threads", path.display(), rayon::current_num_threads());
    println!("| read | points | best of {RUNS} | throughput |\n|---|---|---|---|");
    row("COPC, chunks through the hierarchy", parallel_seconds, parallel.len());
    row("the same file as plain LAZ", laz_seconds, laz.len());
}
