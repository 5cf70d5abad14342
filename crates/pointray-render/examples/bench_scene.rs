//! Throughput of the CPU renderer on a scene file: frames per second and rays per second.
//!
//! `cargo run --release -p pointray-render --example bench_scene -- [SCENE.toml] [FRAMES] [OUT.png]`
//! (default: `scenes/bunny_floor.toml`, the bunny on a reflective floor at 640x640 with
//! shadows and reflections, and 5 timed frames after one warm-up frame). With `OUT.png`,
//! the warm-up frame is written there, to look at what was timed.

use std::error::Error;
use std::path::PathBuf;
use std::time::Instant;

use pointray_cpu::{CpuRenderer, RayCounts};
use pointray_io::image_output::write_png_srgb;
use pointray_scene::{LoadOptions, load_scene};

fn main() -> Result<(), Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let scene_path = args
        .next()
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bunny_floor.toml"));
    let frames: u32 = args.next().map(|n| n.parse()).transpose()?.unwrap_or(5).max(1);
    let image_path = args.next().map(PathBuf::from);

    let started = Instant::now();
    let loaded = load_scene(&scene_path, &LoadOptions::default())?;
    println!("loaded and prepped {} in {:.2} s", scene_path.display(), started.elapsed().as_secs_f64());

    let started = Instant::now();
    let renderer = CpuRenderer::new(&loaded.scene);
    println!("built the BVHs in {:.3} s", started.elapsed().as_secs_f64());

    let settings = loaded.settings;
    let (warm_up, _) = renderer.render_counting_rays(&settings);
    let hits = warm_up.hit_mask().iter().filter(|&&hit| hit).count();
    println!(
        "{}x{}, spp {}, max depth {}, shadows {}, {:?} test: {:.1}% of pixels hit; {} threads",
        settings.width,
        settings.height,
        settings.samples_per_pixel,
        settings.max_depth,
        settings.shadows,
        settings.acceptance,
        100.0 * hits as f64 / warm_up.pixel_count() as f64,
        rayon::current_num_threads()
    );

    if let Some(path) = &image_path {
        write_png_srgb(path, warm_up.width, warm_up.height, &warm_up.color)?;
        println!("wrote {}", path.display());
    }

    let mut total = RayCounts::default();
    let started = Instant::now();
    for _ in 0..frames {
        total += renderer.render_counting_rays(&settings).1;
    }
    let seconds = started.elapsed().as_secs_f64();
    println!(
        "{frames} frames in {seconds:.3} s: {:.2} FPS, {:.1} ms/frame, {:.2} Mrays/s \
         ({} primary + {} shadow + {} reflection rays per frame)",
        frames as f64 / seconds,
        1e3 * seconds / frames as f64,
        total.total() as f64 / seconds / 1e6,
        total.primary / frames as u64,
        total.shadow / frames as u64,
        total.reflection / frames as u64,
    );
    Ok(())
}
