//! `pointray view`: an interactive window on a scene.
//!
//! With the Vulkan backend every frame goes straight from the ray-tracing pipeline to the
//! window, on one device (`Presentation::Direct`): the renderer is made for the window
//! (`VulkanRenderer::for_window`) and its `WindowTarget` traces the display output into a
//! device-local buffer and copies it into the swapchain image. The CPU renderer's frames are
//! in host memory; they are uploaded to the viewer's own swapchain (`present`,
//! `Presentation::HostCopy`).
//!
//! While the view is still, the image is refined progressively (`refinement`): each pass
//! takes the samples after those already taken, and the window shows the mean of them all,
//! summed on the GPU for the direct path and on the host for the CPU renderer
//! (`host_accumulation`); any change starts again from sample 0. With the CPU backend,
//! moving views are previewed at reduced resolution. A scripted turntable
//! (`Script`) renders a fixed number of frames along an orbit, for tests and videos.

mod app;
mod camera_rig;
mod controls;
mod display_image;
mod error;
mod frame_source;
mod frame_stats;
mod host_accumulation;
mod pixels;
mod present;
mod refinement;
mod render_times;
mod screenshots;
mod view_state;

use std::path::PathBuf;
use std::sync::Arc;

use pointray_render::BackendChoice;
use pointray_scene::{Camera, RenderSettings, Scene};
use pointray_vulkan::{DeviceOptions, DeviceSelector, MessageCounter};
use winit::event_loop::EventLoop;
use winit::raw_window_handle::HasDisplayHandle;

pub use camera_rig::CameraRig;
pub use controls::KEY_HELP;
pub use error::ViewerError;
pub use frame_source::Presentation;
pub use pointray_scene::orbit_camera;
pub use screenshots::sequence_path;

use app::App;
use frame_source::FrameSource;
use view_state::ViewState;

/// A scripted run: `frames` frames along a turntable orbit, then exit.
#[derive(Clone, Debug, PartialEq)]
pub struct Script {
    pub frames: u32,
    /// RenderedImage `i` is the scene camera turned by `arc_degrees * i / frames` (see `orbit_camera`).
    pub arc_degrees: f32,
    /// The last frame is saved here (PNG or EXR).
    pub screenshot: Option<PathBuf>,
    /// Every frame is saved here as `frame-NNNNN.png`.
    pub sequence: Option<PathBuf>,
}

#[derive(Clone, Debug)]
pub struct ViewerOptions {
    pub backend: BackendChoice,
    pub device: DeviceSelector,
    /// How devices open. With validation, the Khronos layer runs on the presenter and the
    /// renderer: any message, during the run or at teardown (leaked objects), fails the run
    /// with `ViewerError::Validation`.
    pub device_options: DeviceOptions,
    pub vsync: bool,
    /// `None`: interactive until the window is closed.
    pub script: Option<Script>,
}

/// What a finished run did.
#[derive(Clone, Debug)]
pub struct ViewerSummary {
    pub backend: String,
    /// How the frames reached the window.
    pub presentation: Presentation,
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
    let event_loop = event_loop()?;
    let display = event_loop.display_handle().map_err(|e| ViewerError::Window(e.to_string()))?.as_raw();
    let view_size = (settings.width, settings.height);
    let source = FrameSource::open(
        options.backend,
        &options.device,
        options.device_options,
        &scene,
        view_size,
        Some(display),
    )?;
    let backend = source.describe();
    let presentation = source.presentation();
    println!("backend: {backend}, presentation: {presentation:?}");
    if source.is_cpu() && options.device_options.gpu_memory.is_some() {
        eprintln!("note: the GPU memory budget goes unused: the CPU backend renders");
    }
    if options.script.is_none() {
        println!("{KEY_HELP}");
    }
    // Kept past the renderer's drop: objects leaked at teardown are reported then.
    let renderer_messages = source.message_counter();
    let mut app = App::new(source, ViewState::new(scene, settings), options);
    let looped = event_loop.run_app(&mut app);
    let presenter_messages = app.source.presenter_messages();
    app.close_window();
    let App { source, error, frames_presented, view, .. } = app;
    drop(source);
    let messages = messages_of(renderer_messages) + messages_of(presenter_messages);
    if let Some(error) = error {
        return Err(error);
    }
    looped.map_err(|e| ViewerError::Window(e.to_string()))?;
    if messages > 0 {
        return Err(ViewerError::Validation(messages));
    }
    Ok(ViewerSummary {
        backend,
        presentation,
        frames_presented,
        final_camera: view.scene.camera,
        settings: view.settings,
    })
}

fn messages_of(counter: Option<Arc<MessageCounter>>) -> u32 {
    counter.map_or(0, |counter| counter.count())
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
