//! What the viewer's window tests share: a virtual display, skipping outside CI, the set-up
//! of a scripted run, and image comparison. Each test binary is its own process, as winit's event loop may be created
//! once per process.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use pointray_render::BackendChoice;
use pointray_scene::{LoadOptions, LoadedScene, RenderSettings, load_demo};
use pointray_viewer::{Script, ViewerOptions};
use pointray_vulkan::{DeviceOptions, DeviceSelector};

pub use pointray_test_support::in_ci;

/// Skips (with a note) outside CI; fails in CI.
pub fn missing(what: &str) {
    assert!(!in_ci(), "CI=true but {what}");
    eprintln!("note: skipping, {what}");
}

/// An Xvfb server started for this test, stopped when dropped.
pub struct VirtualDisplay(Child);

impl Drop for VirtualDisplay {
    fn drop(&mut self) {
        // SIGTERM lets Xvfb remove its socket and lock file; a killed server leaves them behind.
        let terminated = Command::new("kill").arg(self.0.id().to_string()).status();
        if !terminated.is_ok_and(|status| status.success()) {
            let _ = self.0.kill();
        }
        let _ = self.0.wait();
    }
}

/// Uses `DISPLAY` when set; otherwise starts Xvfb on a display it picks itself.
pub fn display() -> Result<Option<VirtualDisplay>, String> {
    if std::env::var_os("DISPLAY").is_some() {
        return Ok(None);
    }
    // `-displayfd` makes Xvfb choose a free display and write its number only once it accepts
    // connections, so neither a display in use nor a stale socket can be mistaken for it.
    let mut child = Command::new("Xvfb")
        .args(["-displayfd", "1", "-screen", "0", "640x480x24", "-nolisten", "tcp"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| format!("Xvfb cannot be started ({e}); run scripts/install-system-deps.sh"))?;
    let announcement = child.stdout.take().expect("Xvfb's stdout is piped");
    let server = VirtualDisplay(child);
    let number = announced_display(announcement)?;
    // SAFETY: set before any thread of this test binary reads the environment (each binary has
    // one test, and the viewer starts after this).
    unsafe { std::env::set_var("DISPLAY", format!(":{number}")) };
    Ok(Some(server))
}

/// The display number Xvfb writes to `-displayfd` when it is ready.
fn announced_display(announcement: ChildStdout) -> Result<u32, String> {
    let (sender, receiver) = mpsc::channel();
    std::thread::spawn(move || {
        let mut line = String::new();
        let read = BufReader::new(announcement).read_line(&mut line).map(|_| line);
        let _ = sender.send(read);
    });
    let line = receiver
        .recv_timeout(Duration::from_secs(30))
        .map_err(|_| "Xvfb did not announce a display within 30 s".to_string())?
        .map_err(|e| format!("Xvfb's display number cannot be read: {e}"))?;
    line.trim().parse().map_err(|_| format!("Xvfb exited without a display (it wrote {line:?})"))
}

/// The demo scene, with a display for the test's windows kept open while this lives.
pub struct DemoOnDisplay {
    pub loaded: LoadedScene,
    _display: Option<VirtualDisplay>,
}

/// `None`, after the note `missing` prints, when no display can be had (outside CI).
pub fn demo_on_display() -> Option<DemoOnDisplay> {
    let display = match display() {
        Ok(display) => display,
        Err(problem) => {
            missing(&problem);
            return None;
        }
    };
    let loaded = load_demo(&LoadOptions::default()).expect("the demo scene loads");
    Some(DemoOnDisplay { loaded, _display: display })
}

/// A scripted orbit of the demo at 96x72 under the validation layer, without vsync, saving its
/// last frame as `screenshot` (and every frame under `sequence`, when asked) in `dir`.
pub struct ScriptedRun {
    pub settings: RenderSettings,
    pub options: ViewerOptions,
    pub screenshot: PathBuf,
    pub sequence: Option<PathBuf>,
    pub dir: tempfile::TempDir,
    pub demo: DemoOnDisplay,
}

/// The orbit the script follows, and whether every frame is saved.
pub struct Orbit {
    pub frames: u32,
    pub arc_degrees: f32,
    pub keep_sequence: bool,
}

/// `None` when the test is skipped for want of a display (see `demo_on_display`).
pub fn scripted_run(backend: BackendChoice, samples_per_pixel: u32, orbit: Orbit) -> Option<ScriptedRun> {
    let demo = demo_on_display()?;
    let settings = RenderSettings { width: 96, height: 72, samples_per_pixel, ..demo.loaded.settings };
    let dir = tempfile::tempdir().expect("a temporary folder");
    let screenshot = dir.path().join("viewer.png");
    let sequence = orbit.keep_sequence.then(|| dir.path().join("sequence"));
    let options = ViewerOptions {
        backend,
        device: DeviceSelector::Auto,
        vsync: false,
        device_options: DeviceOptions::VALIDATED,
        script: Some(Script {
            frames: orbit.frames,
            arc_degrees: orbit.arc_degrees,
            screenshot: Some(screenshot.clone()),
            sequence: sequence.clone(),
        }),
    };
    Some(ScriptedRun { settings, options, screenshot, sequence, dir, demo })
}

pub fn read_png(path: &Path) -> image::RgbImage {
    image::open(path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display())).to_rgb8()
}

pub fn psnr(a: &image::RgbImage, b: &image::RgbImage) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions(), "image sizes differ");
    pointray_test_support::psnr_bytes(a.as_raw(), b.as_raw())
}
