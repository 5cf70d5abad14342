//! Measures `prep` and the patch store on points sampled from a mesh:
//!
//! ```text
//! cargo run --release -p pointray-surface --example prep_bench -- MESH.ply [COUNT] [SEED] [blue]
//! ```
//!
//! Prints `prep`'s per-stage wall times and peak resident memory (the whole process's, with the
//! mesh; `prep_owned` frees the sampled positions once recentred, as `pointray prep` does),
//! then the store's write time, bytes a patch and load time (median of 5 loads), compact (as
//! `pointray prep` writes it) and with the full records (version 7's). A measurement, not a
//! test: bench/PREP.md and bench/RESULTS.md record its output.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use pointray_io::formats::ply;
use pointray_patches::patch_store::{self, Encoding};
use pointray_patches::{PatchSet, PrepSettings};
use pointray_surface::peak_memory::{StagePeaks, current_rss};
use pointray_surface::{NoProgress, prep_owned, sample_mesh};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let mesh_path = PathBuf::from(args.next().ok_or("usage: prep_bench MESH.ply [COUNT] [SEED] [blue]")?);
    let count: usize = args.next().map_or(Ok(1_000_000), |a| a.parse())?;
    let seed: u64 = args.next().map_or(Ok(1), |a| a.parse())?;
    let blue_noise = args.next().as_deref() == Some("blue");
    let mesh = ply::read_triangle_mesh(&mesh_path)?;
    let start = Instant::now();
    let cloud = sample_mesh(&mesh, count, seed, blue_noise);
    let kind = if blue_noise { "blue-noise" } else { "uniform" };
    let elapsed = seconds(start.elapsed());
    println!("sampled {} {kind} points from {} in {elapsed:.3} s", cloud.len(), mesh_path.display());
    println!("rayon threads: {}", rayon::current_num_threads());
    let (before, points) = (current_rss().unwrap_or(0), cloud.len());
    let peaks = StagePeaks::new(&NoProgress);
    let (patches, report) = prep_owned(cloud, &PrepSettings::default(), &peaks)?;
    println!("{report}");
    print_peaks(&peaks, before, points);
    let directory = tempfile::tempdir()?;
    for encoding in [Encoding::Compact, Encoding::Full] {
        measure_store(&directory.path().join(format!("{encoding:?}.patches")), &patches, encoding)?;
    }
    Ok(())
}

/// Each stage's peak resident memory, in MB and bytes per input point.
fn print_peaks(peaks: &StagePeaks, before: u64, points: usize) {
    let megabytes = |bytes: u64| bytes as f64 / 1e6;
    let per_point = |bytes: u64| bytes as f64 / points.max(1) as f64;
    println!("peak resident memory (whole process; {:.0} MB before prep):", megabytes(before));
    for (stage, bytes) in peaks.peaks() {
        println!("  {:<22} {:>9.0} MB {:>6.0} B/point", stage.name(), megabytes(bytes), per_point(bytes));
    }
    if let Some(bytes) = peaks.overall() {
        println!("  {:<22} {:>9.0} MB {:>6.0} B/point", "overall", megabytes(bytes), per_point(bytes));
    }
}

/// Writes `patches` to `store` in `encoding` and prints the write time, the bytes a patch
/// and the load time (median of 5 loads, the file in the page cache). The full records are
/// version 7's 68 bytes a patch, read without decoding as version 7 read them.
fn measure_store(
    store: &Path,
    patches: &PatchSet,
    encoding: Encoding,
) -> Result<(), Box<dyn std::error::Error>> {
    let start = Instant::now();
    pointray_io::write_atomically(store, |file| {
        let mut writer = std::io::BufWriter::new(file);
        patch_store::write_to(&mut writer, patches, encoding, store).map_err(std::io::Error::other)?;
        std::io::Write::flush(&mut writer)
    })?;
    let written = seconds(start.elapsed());
    let bytes = std::fs::metadata(store)?.len();
    let per_patch = bytes as f64 / patches.len().max(1) as f64;
    println!(
        "{encoding:?} store write: {written:.3} s, {:.1} MB, {per_patch:.2} bytes a patch",
        bytes as f64 / 1e6
    );
    let mut loads: Vec<Duration> = (0..5)
        .map(|_| {
            let start = Instant::now();
            let loaded = patch_store::read(store).map(|p| p.len());
            (start.elapsed(), loaded)
        })
        .map(|(time, loaded)| loaded.map(|_| time))
        .collect::<Result<_, _>>()?;
    loads.sort();
    println!("{encoding:?} store load (median of 5, file in page cache): {:.3} s", seconds(loads[2]));
    Ok(())
}

fn seconds(duration: Duration) -> f64 {
    duration.as_secs_f64()
}
