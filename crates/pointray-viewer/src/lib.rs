//! `pointray view`: an interactive window on a scene (issue 6).
//!
//! Every frame is rendered by the chosen backend (the Vulkan ray tracer, or the CPU renderer)
//! into host memory, as both renderers return their `Frame` there, and then shown through the
//! viewer's own Vulkan swapchain: the pixels are written to a staging buffer and copied into
//! the swapchain image (`present`). The renderer's device is preferred for presentation.
//!
//! While the view is still, the image is refined progressively (`refinement`); with the CPU
//! backend, moving views are previewed at reduced resolution. A scripted turntable
//! (`Script`) renders a fixed number of frames along an orbit, for tests and videos.

mod app;
mod camera_rig;
mod controls;
mod error;
mod frame_source;
mod frame_stats;
mod orbit;
mod pixels;
mod present;
mod refinement;
mod render_times;
mod screenshots;
mod teardown_messages;
mod view_state;

use std::path::PathBuf;

use pointray_scene::{Camera, RenderSettings, Scene};
use pointray_vulkan::DeviceSelector;
use winit::event_loop::EventLoop;

pub use camera_rig::CameraRig;
pub use controls::KEY_HELP;
pub use error::ViewerError;
pub use frame_source::RenderBackend;
pub use orbit::orbit_camera;

use app::App;
use frame_source::FrameSource;
use teardown_messages::count_validation_messages;
use view_state::ViewState;

/// A scripted run: `frames` frames along a turntable orbit, then exit.
#[derive(Clone, Debug, PartialEq)]
pub struct Script {
    pub frames: u32,
    /// Frame `i` is the scene camera turned by `arc_degrees * i / frames` (see `orbit_camera`).
    pub arc_degrees: f32,
    /// The last frame is saved here (PNG or EXR).
    pub screenshot: Option<PathBuf>,
    /// Every frame is saved here as `frame-NNNNN.png`.
    pub sequence: Option<PathBuf>,
}

#[derive(Clone, Debug)]
pub struct ViewerOptions {
    pub backend: RenderBackend,
    pub device: DeviceSelector,
    pub vsync: bool,
    /// The Khronos validation layer on the presenter and the renderer: any message, during
    /// the run or at teardown (leaked objects), fails the run with `ViewerError::Validation`.
    pub validation: bool,
    /// `None`: interactive until the window is closed.
    pub script: Option<Script>,
}

/// What a finished run did.
#[derive(Clone, Debug)]
pub struct ViewerSummary {
    pub backend: String,
    pub frames_presented: u64,
    /// The camera of the last frame.
    pub final_camera: Camera,
    pub settings: RenderSettings,
}

/// Opens the window and runs until it is closed, Escape is pressed, or the script ends.
/// The event loop may be created once per process.
pub fn run_viewer(
    scene: Scene,
    settings: RenderSettings,
    options: ViewerOptions,
) -> Result<ViewerSummary, ViewerError> {
    if let Some(dir) = options.script.as_ref().and_then(|s| s.sequence.as_ref()) {
        std::fs::create_dir_all(dir)
            .map_err(|source| ViewerError::SequenceDir { path: dir.clone(), source })?;
    }
    let source = FrameSource::open(options.backend, &options.device, options.validation, &scene)?;
    let backend = source.describe();
    println!("backend: {backend}");
    if options.script.is_none() {
        println!("{KEY_HELP}");
    }
    let event_loop = event_loop()?;
    let mut app = App::new(source, ViewState::new(scene, settings), options);
    let looped = event_loop.run_app(&mut app);
    app.close_window();
    let presenter_messages = app.presenter_messages.as_ref().map_or(0, |counter| counter.count());
    // Moved out (App has no `Drop`) to be dropped where its teardown's messages are counted.
    let messages = presenter_messages + renderer_messages_through_teardown(app.source);
    if let Some(error) = app.error.take() {
        return Err(error);
    }
    looped.map_err(|e| ViewerError::Window(e.to_string()))?;
    if messages > 0 {
        return Err(ViewerError::Validation(messages));
    }
    Ok(ViewerSummary {
        backend,
        frames_presented: app.frames_presented,
        final_camera: app.view.scene.camera,
        settings: app.view.settings,
    })
}

/// The renderer's validation messages: those of the run, then those its drop reports
/// (leaked objects). The presenter's are counted apart: its counter outlives its instance.
fn renderer_messages_through_teardown(source: FrameSource) -> u32 {
    let during_run = source.validation_messages();
    during_run + count_validation_messages(|| drop(source))
}

/// On X11 and Wayland the loop may run off the main thread, so tests can open a window.
fn event_loop() -> Result<EventLoop<()>, ViewerError> {
    let mut builder = EventLoop::builder();
    #[cfg(target_os = "linux")]
    {
        use winit::platform::x11::EventLoopBuilderExtX11;
        builder.with_any_thread(true);
    }
    builder.build().map_err(|e| ViewerError::Window(e.to_string()))
}
