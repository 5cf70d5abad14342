//! What the viewer's window tests share: a virtual display, skipping outside CI, and image
//! comparison. Each test binary is its own process, as winit's event loop may be created
//! once per process.

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

pub fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// Skips (with a note) outside CI; fails in CI.
pub fn missing(what: &str) {
    assert!(!in_ci(), "CI=true but {what}");
    eprintln!("note: skipping, {what}");
}

/// An Xvfb server started for this test, killed (by its own pid) when dropped.
pub struct VirtualDisplay(Child);

impl Drop for VirtualDisplay {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Uses `DISPLAY` when set; otherwise starts Xvfb on a display numbered after this process.
pub fn display() -> Result<Option<VirtualDisplay>, String> {
    if std::env::var_os("DISPLAY").is_some() {
        return Ok(None);
    }
    let name = format!(":{}", 99 + std::process::id() % 400);
    let child = Command::new("Xvfb")
        .args([name.as_str(), "-screen", "0", "640x480x24", "-nolisten", "tcp"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| format!("Xvfb cannot be started ({e}); run scripts/install-system-deps.sh"))?;
    let server = VirtualDisplay(child);
    let socket = format!("/tmp/.X11-unix/X{}", &name[1..]);
    for _ in 0..100 {
        if Path::new(&socket).exists() {
            // SAFETY: set before any thread of this test binary reads the environment (each
            // binary has one test, and the viewer starts after this).
            unsafe { std::env::set_var("DISPLAY", &name) };
            return Ok(Some(server));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    Err(format!("Xvfb did not open {socket}"))
}

pub fn read_png(path: &Path) -> image::RgbImage {
    image::open(path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display())).to_rgb8()
}

pub fn psnr(a: &image::RgbImage, b: &image::RgbImage) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions(), "image sizes differ");
    let squared: f64 = a.as_raw().iter().zip(b.as_raw()).map(|(&x, &y)| (x as f64 - y as f64).powi(2)).sum();
    let mse = squared / a.as_raw().len() as f64;
    if mse == 0.0 { f64::INFINITY } else { 10.0 * (255.0f64 * 255.0 / mse).log10() }
}
