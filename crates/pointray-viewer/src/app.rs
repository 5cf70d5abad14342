//! The window and its frame loop (winit): input to camera and toggles, draw (render and
//! present, see `frame_source`), title statistics, and the scripted turntable.

use std::collections::HashSet;
use std::time::{Duration, Instant};

use glam::{Vec2, Vec3};
use pointray_scene::{Camera, RenderSettings, RenderedImage};
use winit::application::ApplicationHandler;
use winit::dpi::{PhysicalPosition, PhysicalSize};
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::{Window, WindowId};

use crate::controls::{self, Action};
use crate::error::ViewerError;
use crate::frame_source::{Drawn, FrameSource, Presentation};
use crate::frame_stats::FrameStats;
use crate::refinement::{Pass, Refinement};
use crate::render_times::RenderTimes;
use crate::screenshots;
use crate::view_state::ViewState;
use crate::{Script, ViewerOptions};
use pointray_scene::orbit_camera;
use pointray_vulkan::TileResidency;

/// The longest an interactive frame spends loading a streamed scene's tiles (at least one
/// tile a frame): a moving camera keeps about 30 frames a second while they come.
const STREAM_STEP: Duration = Duration::from_millis(30);

/// The scripted run's progress.
struct ScriptRun {
    script: Script,
    start: Camera,
    next_frame: u32,
    render_times: RenderTimes,
}

#[derive(Default)]
struct Mouse {
    position: Option<Vec2>,
    orbiting: bool,
    panning: bool,
}

pub(crate) struct App {
    /// Draws into `window`; `close_window` ends its presentation before the window goes.
    pub(crate) source: FrameSource,
    window: Option<Window>,
    pub(crate) view: ViewState,
    options: ViewerOptions,
    script: Option<ScriptRun>,
    refinement: Refinement,
    stats: FrameStats,
    /// The frame on screen, when it is on the host (always on the host path; on the direct
    /// path only frames read back for a screenshot).
    shown: Option<RenderedImage>,
    mouse: Mouse,
    held: HashSet<KeyCode>,
    last_tick: Instant,
    pub(crate) frames_presented: u64,
    pub(crate) error: Option<ViewerError>,
    /// Where a streamed scene's tiles stood after the last frame.
    residency: Option<TileResidency>,
}

impl App {
    pub(crate) fn new(source: FrameSource, view: ViewState, options: ViewerOptions) -> Self {
        let now = Instant::now();
        let script = options.script.clone().map(|script| ScriptRun {
            script,
            start: view.scene.camera,
            next_frame: 0,
            render_times: RenderTimes::default(),
        });
        Self {
            window: None,
            refinement: Refinement::new(view.settings.samples_per_pixel, now),
            stats: FrameStats::new(now),
            source,
            view,
            options,
            script,
            shown: None,
            mouse: Mouse::default(),
            held: HashSet::new(),
            last_tick: now,
            frames_presented: 0,
            error: None,
            residency: None,
        }
    }

    /// Tears the presentation down before the window it draws into.
    pub(crate) fn close_window(&mut self) {
        self.source.close_window();
        self.window = None;
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: ViewerError) {
        self.error.get_or_insert(error);
        event_loop.exit();
    }

    fn open_window(&mut self, event_loop: &ActiveEventLoop) -> Result<(), ViewerError> {
        let size = PhysicalSize::new(self.view.settings.width, self.view.settings.height);
        // A scripted run's frames are traced at the window's size (the direct path): it keeps
        // the settings' size, so that they are the images `pointray render` makes.
        let attributes = Window::default_attributes()
            .with_title("pointray view")
            .with_inner_size(size)
            .with_resizable(self.script.is_none());
        let window = event_loop.create_window(attributes).map_err(|e| ViewerError::Window(e.to_string()))?;
        let display = window.display_handle().map_err(|e| ViewerError::Window(e.to_string()))?.as_raw();
        let handle = window.window_handle().map_err(|e| ViewerError::Window(e.to_string()))?.as_raw();
        let inner = window.inner_size();
        let size = (inner.width, inner.height);
        self.source.attach_window(
            display,
            handle,
            size,
            self.options.vsync,
            self.options.device_options.validation,
        )?;
        self.window = Some(window);
        Ok(())
    }

    fn redraw(&mut self) -> Result<(), ViewerError> {
        let started = Instant::now();
        let drawn = match &mut self.script {
            Some(_) => Some(self.scripted_frame()?),
            None => self.interactive_frame(started)?,
        };
        let shown = match drawn {
            Some(Drawn { shown, frame }) => {
                self.shown = frame;
                shown
            }
            // Nothing new: the host path shows its frame again (the window may have changed).
            None => match &self.shown {
                Some(frame) => self.source.show_again(frame)?,
                None => false,
            },
        };
        self.frames_presented += u64::from(shown);
        if let Some((fps, mean)) = self.stats.record(Instant::now(), started.elapsed()) {
            let path = match self.source.presentation() {
                Presentation::Direct => "direct",
                Presentation::HostCopy => "host copy",
            };
            let tiles = self.residency.map(|tiles| {
                format!(", {} of {} tiles in full, {} coarse", tiles.resident, tiles.tiles, tiles.coarse)
            });
            let title = format!(
                "pointray view: {fps:.1} fps, {:.1} ms/frame, {} spp, {}, {path}{}",
                mean.as_secs_f64() * 1e3,
                self.refinement.taken().max(self.view.settings.samples_per_pixel),
                self.source.describe(),
                tiles.unwrap_or_default()
            );
            if let Some(window) = &self.window {
                window.set_title(&title);
            }
        }
        Ok(())
    }

    /// RenderedImage `i` of the turntable, at the settings' size and samples, so that it is the
    /// image `pointray render` makes from that camera. Frames to be saved are kept.
    fn scripted_frame(&mut self) -> Result<Drawn, ViewerError> {
        let run = self.script.as_mut().expect("scripted");
        let index = run.next_frame;
        self.view.scene.camera = orbit_camera(&run.start, index, run.script.frames, run.script.arc_degrees);
        run.next_frame += 1;
        let last = run.next_frame == run.script.frames;
        let keep = run.script.sequence.is_some() || (last && run.script.screenshot.is_some());
        // Every tile the frame needs, as `pointray render` loads them.
        self.stream_tiles(self.view.settings.aspect(), None)?;
        let started = Instant::now();
        let drawn = self.source.draw(&self.view.scene, &self.view.settings, keep)?;
        let run = self.script.as_mut().expect("scripted");
        run.render_times.record(started.elapsed());
        if let (Some(dir), Some(frame)) = (&run.script.sequence, &drawn.frame) {
            screenshots::save(frame, &screenshots::sequence_path(dir, index))?;
        }
        Ok(drawn)
    }

    fn interactive_frame(&mut self, now: Instant) -> Result<Option<Drawn>, ViewerError> {
        let step = controls::fly_direction(&self.held);
        let seconds = now.duration_since(self.last_tick).as_secs_f32().min(0.1);
        self.last_tick = now;
        if step != Vec3::ZERO {
            self.view.rig.fly(step * seconds);
            self.refinement.restart(now);
        }
        self.view.sync_camera();
        let size = self.window.as_ref().map(Window::inner_size).unwrap_or(PhysicalSize::new(1, 1));
        // A minimised window has no view to load tiles for: the ones held stay.
        if size.width > 0 && size.height > 0 {
            self.stream_tiles(size.width as f32 / size.height as f32, Some(STREAM_STEP))?;
        }
        let Some(pass) = self.refinement.next(now, self.source.is_cpu()) else { return Ok(None) };
        let settings = self.pass_settings(pass);
        Ok(Some(self.source.draw(&self.view.scene, &settings, false)?))
    }

    /// Loads the tiles the camera needs, for at most `limit`; a change restarts the refinement.
    fn stream_tiles(&mut self, aspect: f32, limit: Option<Duration>) -> Result<(), ViewerError> {
        self.residency = self.source.stream_tiles(&self.view.scene, aspect, limit)?;
        if self.residency.is_some_and(|residency| residency.changed()) {
            self.refinement.restart(Instant::now());
        }
        Ok(())
    }

    /// The window's size (divided for previews) and the pass's samples.
    fn pass_settings(&self, pass: Pass) -> RenderSettings {
        let size = self.window.as_ref().map(Window::inner_size).unwrap_or(PhysicalSize::new(1, 1));
        RenderSettings {
            width: (size.width / pass.divisor).max(1),
            height: (size.height / pass.divisor).max(1),
            samples_per_pixel: pass.samples_per_pixel,
            first_sample: pass.first_sample,
            ..self.view.settings
        }
    }

    /// After the last scripted frame: the screenshot, then the end of the loop.
    fn finish_script(&mut self, event_loop: &ActiveEventLoop) -> Result<(), ViewerError> {
        let Some(run) = &self.script else { return Ok(()) };
        if run.next_frame < run.script.frames {
            return Ok(());
        }
        if let (Some(path), Some(frame)) = (&run.script.screenshot, &self.shown) {
            screenshots::save(frame, path)?;
        }
        if let Some(summary) = run.render_times.summary() {
            println!("{summary}");
        }
        event_loop.exit();
        Ok(())
    }

    fn key(&mut self, event_loop: &ActiveEventLoop, event: &KeyEvent) -> Result<(), ViewerError> {
        let PhysicalKey::Code(code) = event.physical_key else { return Ok(()) };
        if event.state == ElementState::Released {
            self.held.remove(&code);
            return Ok(());
        }
        self.held.insert(code);
        if event.repeat || self.script.is_some() {
            return Ok(());
        }
        match controls::action_for(code) {
            Some(Action::Quit) => event_loop.exit(),
            Some(Action::Screenshot) => self.save_screenshot()?,
            Some(Action::ToggleVsync) => {
                if let Some(vsync) = self.source.toggle_vsync() {
                    println!("vsync {}", if vsync { "on" } else { "off" });
                }
            }
            Some(action) if self.view.apply(action) => self.refinement.restart(Instant::now()),
            Some(_) | None => {}
        }
        Ok(())
    }

    /// Saves what is on screen; the direct path reads back one more pass, which adds its
    /// samples to what is shown.
    fn save_screenshot(&mut self) -> Result<(), ViewerError> {
        if self.source.presentation() == Presentation::Direct && self.refinement.taken() > 0 {
            let pass = self.refinement.one_more();
            let settings = self.pass_settings(pass);
            let drawn = self.source.draw(&self.view.scene, &settings, true)?;
            self.frames_presented += u64::from(drawn.shown);
            self.shown = drawn.frame;
        }
        let Some(frame) = &self.shown else { return Ok(()) };
        let path = screenshots::next_screenshot_path(std::path::Path::new("."));
        screenshots::save(frame, &path)?;
        println!("saved {}", path.display());
        Ok(())
    }

    fn mouse_moved(&mut self, position: PhysicalPosition<f64>) {
        let position = Vec2::new(position.x as f32, position.y as f32);
        let delta = self.mouse.position.map(|last| position - last).unwrap_or(Vec2::ZERO);
        self.mouse.position = Some(position);
        if self.script.is_some() || delta == Vec2::ZERO {
            return;
        }
        if self.mouse.orbiting {
            self.view.rig.orbit(delta);
        } else if self.mouse.panning {
            let height = self.window.as_ref().map_or(1, |w| w.inner_size().height);
            self.view.rig.pan(delta, height);
        } else {
            return;
        }
        self.refinement.restart(Instant::now());
    }

    fn handle(&mut self, event_loop: &ActiveEventLoop, event: WindowEvent) -> Result<(), ViewerError> {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                self.source.resize(size.width, size.height);
                self.refinement.restart(Instant::now());
            }
            WindowEvent::KeyboardInput { event, .. } => self.key(event_loop, &event)?,
            WindowEvent::MouseInput { state, button, .. } => {
                let pressed = state == ElementState::Pressed;
                match button {
                    MouseButton::Left => self.mouse.orbiting = pressed,
                    MouseButton::Right | MouseButton::Middle => self.mouse.panning = pressed,
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => self.mouse_moved(position),
            WindowEvent::MouseWheel { delta, .. } if self.script.is_none() => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.view.rig.zoom(lines);
                self.refinement.restart(Instant::now());
            }
            WindowEvent::RedrawRequested => {
                self.redraw()?;
                self.finish_script(event_loop)?;
            }
            _ => {}
        }
        Ok(())
    }

    /// Whether frames must keep coming without input.
    fn busy(&self) -> bool {
        self.script.is_some()
            || !self.refinement.done()
            || controls::fly_direction(&self.held) != Vec3::ZERO
            || self.residency.is_some_and(|residency| residency.pending > 0)
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        if let Err(error) = self.open_window(event_loop) {
            self.fail(event_loop, error);
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        if let Err(error) = self.handle(event_loop, event) {
            self.fail(event_loop, error);
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if self.busy() {
            event_loop.set_control_flow(ControlFlow::Poll);
            if let Some(window) = &self.window {
                window.request_redraw();
            }
        } else {
            event_loop.set_control_flow(ControlFlow::Wait);
        }
    }
}
