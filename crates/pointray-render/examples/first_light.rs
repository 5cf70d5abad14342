//! First light on a device: renders the bunny (points and mesh, on a reflective floor) and the
//! procedural demo at 640x640, writes PNGs and raw linear images, compares them with a
//! reference run (PSNR, hit-mask agreement) and times re-traces of the bunny.
//!
//! `first_light --data DIR --out DIR [--reference DIR] [--frames N]`
//! (`DIR` of `--data` holds `points/bunny.ply` and `meshes/bunny.ply`.)

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::Vec3;
use pointray_io::formats::ply::read_triangle_mesh;
use pointray_io::image_output::write_png_srgb;
use pointray_io::write_atomically;
use pointray_scene::{BufferLayout, Material, RenderSettings, RenderedImage, Scene, demo_scene};
use pointray_test_support::floor_scenes::{mesh, model_on_floor, object};
use pointray_test_support::prepped_points;
use pointray_vulkan::{BlasLayout, DeviceSelector, PreparedScene, SceneLayout, VulkanRenderer};

type Error = Box<dyn std::error::Error>;

struct Args {
    data: PathBuf,
    out: PathBuf,
    reference: Option<PathBuf>,
    frames: usize,
}

fn parse_args() -> Result<Args, Error> {
    let mut args =
        Args { data: PathBuf::from("data"), out: PathBuf::from("out"), reference: None, frames: 50 };
    let mut words = std::env::args().skip(1);
    while let Some(flag) = words.next() {
        let value = words.next().ok_or_else(|| format!("{flag} needs a value"))?;
        match flag.as_str() {
            "--data" => args.data = value.into(),
            "--out" => args.out = value.into(),
            "--reference" => args.reference = Some(value.into()),
            "--frames" => args.frames = value.parse()?,
            other => return Err(format!("unknown flag {other}").into()),
        }
    }
    Ok(args)
}

fn bunny_scenes(data: &Path) -> Result<Vec<(&'static str, Scene)>, Error> {
    let triangles = read_triangle_mesh(&data.join("meshes/bunny.ply"))?;
    let mesh = object("bunny mesh", mesh(triangles), Material::default());
    let bounds = mesh.world_bounds().ok_or("the bunny mesh is empty")?;
    let points = prepped_points("bunny points", &data.join("points/bunny.ply"), Material::default());
    Ok(vec![
        ("bunny_points", model_on_floor(points, bounds, 0.3)),
        ("bunny_mesh", model_on_floor(mesh, bounds, 0.3)),
    ])
}

/// Colour (3 floats) then instance id (1 u32) per pixel, little-endian, after width and height.
fn write_raw(path: &Path, frame: &RenderedImage) -> Result<(), Error> {
    write_atomically(path, |w| {
        use std::io::Write;
        w.write_all(&frame.width.to_le_bytes())?;
        w.write_all(&frame.height.to_le_bytes())?;
        for (color, id) in frame.color.iter().zip(&frame.instance_id) {
            for channel in color.to_array() {
                w.write_all(&channel.to_le_bytes())?;
            }
            w.write_all(&id.to_le_bytes())?;
        }
        Ok(())
    })?;
    Ok(())
}

fn read_raw(path: &Path) -> Result<(Vec<Vec3>, Vec<u32>), Error> {
    let bytes = std::fs::read(path)?;
    let word =
        |i: usize| u32::from_le_bytes([bytes[4 * i], bytes[4 * i + 1], bytes[4 * i + 2], bytes[4 * i + 3]]);
    let pixels = (word(0) * word(1)) as usize;
    if bytes.len() != 8 + 16 * pixels {
        return Err(format!("{} is truncated", path.display()).into());
    }
    let float = |i| f32::from_bits(word(i));
    let colors =
        (0..pixels).map(|p| Vec3::new(float(2 + 4 * p), float(3 + 4 * p), float(4 + 4 * p))).collect();
    let ids = (0..pixels).map(|p| word(5 + 4 * p)).collect();
    Ok((colors, ids))
}

/// PSNR in dB of colours clamped to [0, 1], and the fraction of pixels whose hit/miss agrees.
fn compare(frame: &RenderedImage, reference: &Path) -> Result<(f64, f64), Error> {
    let (colors, ids) = read_raw(reference)?;
    if colors.len() != frame.color.len() {
        return Err(format!("{} has another size", reference.display()).into());
    }
    let clamp = |c: Vec3| c.clamp(Vec3::ZERO, Vec3::ONE);
    let squared: f64 = frame
        .color
        .iter()
        .zip(&colors)
        .map(|(a, b)| f64::from((clamp(*a) - clamp(*b)).length_squared()))
        .sum();
    let mse = squared / (3 * colors.len()) as f64;
    let psnr = if mse == 0.0 { f64::INFINITY } else { 10.0 * (1.0 / mse).log10() };
    let miss = pointray_scene::RenderedImage::MISS;
    let agree = frame.instance_id.iter().zip(&ids).filter(|(a, b)| (**a == miss) == (**b == miss)).count();
    Ok((psnr, agree as f64 / ids.len() as f64))
}

fn milliseconds(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// Median and minimum GPU trace time and median wall time over `frames` re-traces.
fn time_traces(
    renderer: &VulkanRenderer,
    scene: &PreparedScene,
    settings: &RenderSettings,
    frames: usize,
) -> Result<String, Error> {
    for _ in 0..3 {
        renderer.trace(scene, settings)?;
    }
    let mut gpu = Vec::new();
    let mut wall = Vec::new();
    for _ in 0..frames.max(1) {
        let (_, timing) = renderer.trace_timed(scene, settings)?;
        gpu.extend(timing.gpu.map(milliseconds));
        wall.push(milliseconds(timing.wall));
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
    };
    let gpu_min = gpu.iter().copied().fold(f64::INFINITY, f64::min);
    let gpu_median = median(&mut gpu);
    Ok(format!(
        "gpu trace median {gpu_median:.3} ms (min {gpu_min:.3} ms, {:.0} fps), wall per trace call median {:.2} ms, {} frames",
        1e3 / gpu_median,
        median(&mut wall),
        frames.max(1)
    ))
}

fn main() -> Result<(), Error> {
    let args = parse_args()?;
    std::fs::create_dir_all(&args.out)?;
    let renderer = VulkanRenderer::new(DeviceSelector::Auto, pointray_vulkan::DeviceOptions::default())?;
    println!("device: {}", renderer.device_info());
    let mut scenes = bunny_scenes(&args.data)?;
    scenes.push(("demo", demo_scene()?));
    let settings = RenderSettings { width: 640, height: 640, ..RenderSettings::default() };
    for (name, scene) in &scenes {
        let start = Instant::now();
        let prepared = renderer.prepare(scene)?;
        let prepare_ms = milliseconds(start.elapsed());
        let frame = renderer.trace(&prepared, &settings)?;
        write_png_srgb(&args.out.join(format!("{name}.png")), frame.width, frame.height, &frame.color)?;
        write_raw(&args.out.join(format!("{name}.rgbi")), &frame)?;
        println!("{name}: prepared in {prepare_ms:.1} ms");
        if let Some(reference) = &args.reference {
            let (psnr, agreement) = compare(&frame, &reference.join(format!("{name}.rgbi")))?;
            println!("{name}: PSNR {psnr:.2} dB vs reference, hit masks agree on {:.4}%", 100.0 * agreement);
        }
        if *name == "bunny_points" {
            println!(
                "{name} 640x640 split buffers: {}",
                time_traces(&renderer, &prepared, &settings, args.frames)?
            );
            let combined = RenderSettings { buffer_layout: BufferLayout::Combined, ..settings };
            let combined_scene = renderer.prepare_with_layout(scene, SceneLayout::for_settings(&combined))?;
            println!(
                "{name} 640x640 combined buffer: {}",
                time_traces(&renderer, &combined_scene, &combined, args.frames)?
            );
            let per_box_layout = SceneLayout { blas: BlasLayout::GeometryPerAabb, ..SceneLayout::default() };
            let per_box = renderer.prepare_with_layout(scene, per_box_layout)?;
            println!(
                "{name} 640x640 geometry per box: {}",
                time_traces(&renderer, &per_box, &settings, args.frames)?
            );
        }
    }
    println!("validation messages: {}", renderer.validation_messages());
    Ok(())
}
