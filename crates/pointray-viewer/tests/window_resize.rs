//! A window target follows its window's size: a real window (Xvfb when there is no display)
//! shows the demo traced straight into its swapchain, is resized, and shows it again at the
//! new size. Each shown frame, read back from the display buffer, is the image a plain trace
//! of that size makes; the validation layer reports nothing, teardown included.

// Only some of the shared helpers are used here.
#[allow(dead_code)]
mod common;

use std::time::{Duration, Instant};

use common::{demo_on_display, missing};
use pointray_scene::{RenderSettings, Scene};
use pointray_vulkan::{
    DeviceOptions, DeviceSelector, DisplayImage, PixelOutput, PreparedScene, Presented, ReadBack,
    TraceTarget, VulkanRenderer, WindowTarget,
};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

const FIRST: (u32, u32) = (96, 72);
const SECOND: (u32, u32) = (128, 80);
/// How long the window system may take to report the resize.
const RESIZE_WAIT: Duration = Duration::from_secs(10);

/// Field order is drop order: the target before the scene, the renderer and the window.
struct Open {
    target: WindowTarget,
    prepared: PreparedScene,
    renderer: VulkanRenderer,
    window: Window,
}

#[derive(Default)]
struct Outcome {
    /// Each shown frame and the same view traced at its size into host memory.
    shown: Vec<(DisplayImage, Vec<u8>)>,
    messages: u32,
    skipped: Option<String>,
    error: Option<String>,
}

struct ResizeRun {
    scene: Scene,
    settings: RenderSettings,
    open: Option<Open>,
    resize_asked: Option<Instant>,
    outcome: Outcome,
}

impl ResizeRun {
    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<Open, String> {
        let size = PhysicalSize::new(FIRST.0, FIRST.1);
        let attributes = Window::default_attributes().with_title("resize test").with_inner_size(size);
        let window = event_loop.create_window(attributes).map_err(|e| e.to_string())?;
        let display = window.display_handle().map_err(|e| e.to_string())?.as_raw();
        let handle = window.window_handle().map_err(|e| e.to_string())?.as_raw();
        let renderer = VulkanRenderer::for_window(DeviceSelector::Auto, DeviceOptions::VALIDATED, display)
            .map_err(|error| {
                if error.is_no_device() {
                    self.outcome.skipped = Some(error.to_string());
                }
                error.to_string()
            })?;
        let prepared = renderer.prepare(&self.scene).map_err(|e| e.to_string())?;
        let inner = window.inner_size();
        let target = WindowTarget::new(&renderer, display, handle, (inner.width, inner.height), false)
            .map_err(|e| e.to_string())?;
        Ok(Open { target, prepared, renderer, window })
    }

    /// Presents the view, keeps it, and traces the same view at the shown size.
    fn show(&mut self) -> Result<(), String> {
        let open = self.open.as_mut().ok_or("the window is not open")?;
        let presented = open
            .target
            .present(&open.renderer, &open.prepared, &self.settings, ReadBack::Keep)
            .map_err(|e| e.to_string())?;
        if presented != Presented::Shown {
            return Err(format!("the frame was not shown: {presented:?}"));
        }
        let shown = open.target.shown_rgba8().map_err(|e| e.to_string())?;
        let sized = RenderSettings { width: shown.width, height: shown.height, ..self.settings };
        let mut plain = TraceTarget::new(PixelOutput::Display);
        open.renderer.trace_into(&open.prepared, &sized, &mut plain).map_err(|e| e.to_string())?;
        let traced = plain.display_rgba8().map_err(|e| e.to_string())?.to_vec();
        self.outcome.shown.push((shown, traced));
        Ok(())
    }

    fn step(&mut self, event_loop: &ActiveEventLoop, event: &WindowEvent) -> Result<(), String> {
        if let WindowEvent::Resized(size) = event
            && self.resize_asked.is_some()
            && (size.width, size.height) == SECOND
        {
            let open = self.open.as_mut().ok_or("the window is not open")?;
            open.target.resize(size.width, size.height);
            self.show()?;
            self.close();
            event_loop.exit();
        }
        Ok(())
    }

    fn close(&mut self) {
        if let Some(open) = self.open.take() {
            let counter = open.renderer.message_counter();
            drop(open);
            self.outcome.messages = counter.count();
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: String) {
        self.outcome.error.get_or_insert(error);
        self.close();
        event_loop.exit();
    }
}

impl ApplicationHandler for ResizeRun {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.open.is_some() || self.outcome.error.is_some() {
            return;
        }
        let shown = self.open(event_loop).and_then(|open| {
            self.open = Some(open);
            self.show()
        });
        match shown {
            Ok(()) => {
                let open = self.open.as_ref().expect("opened above");
                // On X11 the new size arrives later, as a `Resized` event.
                let _ = open.window.request_inner_size(PhysicalSize::new(SECOND.0, SECOND.1));
                self.resize_asked = Some(Instant::now());
            }
            Err(error) => self.fail(event_loop, error),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        if let Err(error) = self.step(event_loop, &event) {
            self.fail(event_loop, error);
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        event_loop.set_control_flow(ControlFlow::WaitUntil(Instant::now() + Duration::from_millis(50)));
        if self.resize_asked.is_some_and(|asked| asked.elapsed() > RESIZE_WAIT) {
            self.fail(event_loop, format!("no resize to {SECOND:?} was reported"));
        }
    }
}

#[test]
fn window_target_follows_a_resized_window() {
    let Some(demo) = demo_on_display() else { return };
    let settings = RenderSettings { samples_per_pixel: 1, ..demo.loaded.settings };
    let mut builder = EventLoop::builder();
    {
        use winit::platform::x11::EventLoopBuilderExtX11;
        builder.with_any_thread(true);
    }
    let event_loop = builder.build().expect("an event loop");
    let mut run = ResizeRun {
        scene: demo.loaded.scene,
        settings,
        open: None,
        resize_asked: None,
        outcome: Outcome::default(),
    };
    event_loop.run_app(&mut run).expect("the event loop runs");
    let outcome = run.outcome;
    if let Some(reason) = outcome.skipped {
        return missing(&format!("no usable Vulkan device: {reason}"));
    }
    assert_eq!(outcome.error, None, "the run failed");
    let sizes: Vec<(u32, u32)> = outcome.shown.iter().map(|(image, _)| (image.width, image.height)).collect();
    assert_eq!(sizes, vec![FIRST, SECOND], "the shown frames follow the window's size");
    for (image, traced) in &outcome.shown {
        assert!(
            image.rgba8 == *traced,
            "the {}x{} frame shown differs from a plain trace",
            image.width,
            image.height
        );
    }
    assert_eq!(outcome.messages, 0, "validation messages, teardown included (printed above)");
}
