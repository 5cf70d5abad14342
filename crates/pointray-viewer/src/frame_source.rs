//! Where frames come from and how they reach the window: the Vulkan ray tracer traces
//! straight into the window's swapchain on its own device (`WindowTarget`, the direct path);
//! the CPU renderer's frames are copied from host memory (`present::Presenter`, the host
//! path). Either builds its acceleration structures once; each frame only sets the camera and
//! the lights.

use pointray_cpu::CpuRenderer;
use pointray_render::{Backend, BackendChoice};
use pointray_scene::{Light, RenderSettings, RenderedImage, Scene};
use pointray_vulkan::{
    DeviceOptions, DeviceSelector, MessageCounter, PreparedScene, ReadBack, SceneLayout, TileResidency,
    VulkanRenderer, WindowTarget,
};
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};
use std::sync::Arc;
use std::time::Duration;

use crate::display_image::image_from_display;
use crate::error::ViewerError;
use crate::host_accumulation::continue_mean;
use crate::pixels::image_bytes;
use crate::present::Presenter;

/// How frames reach the window.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Presentation {
    /// Traced into a device-local buffer and copied into the swapchain image on the
    /// renderer's own device: no host round trip.
    Direct,
    /// Rendered into host memory, then uploaded and copied into the swapchain image.
    HostCopy,
}

/// What one drawn frame left on screen.
pub(crate) struct Drawn {
    pub(crate) shown: bool,
    /// The frame as shown: always on the host path, when asked for on the direct path.
    pub(crate) frame: Option<RenderedImage>,
}

pub(crate) enum FrameSource {
    Vulkan {
        // Before the scene and the renderer: their GPU objects go first.
        window: Option<Box<WindowTarget>>,
        prepared: Box<PreparedScene>,
        /// The lights `prepared` shades with.
        lights: Vec<Light>,
        renderer: Box<VulkanRenderer>,
    },
    Cpu {
        // Before the window it draws into is closed (`close_window`).
        presenter: Option<Box<Presenter>>,
        renderer: Box<CpuRenderer>,
        /// The mean of every sample since sample 0 (the GPU keeps its sums on the device).
        accumulated: Option<RenderedImage>,
    },
}

impl FrameSource {
    /// With `display`, a Vulkan renderer can present to that window system's windows. The
    /// backend is chosen by `pointray_render::Backend`'s rule, as every command's is.
    pub(crate) fn open(
        choice: BackendChoice,
        device: &DeviceSelector,
        options: DeviceOptions,
        scene: &Scene,
        view_size: (u32, u32),
        display: Option<RawDisplayHandle>,
    ) -> Result<Self, ViewerError> {
        let backend = match display {
            Some(display) => Backend::open_for_window(choice, device, options, display)?,
            None => Backend::open(choice, device, options)?,
        };
        match backend {
            Backend::Vulkan(renderer) => Ok(Self::Vulkan {
                window: None,
                prepared: Box::new(renderer.prepare_with_layout(scene, streaming_layout(view_size))?),
                lights: scene.lights.clone(),
                renderer,
            }),
            Backend::Cpu => Ok(Self::Cpu {
                presenter: None,
                renderer: Box::new(CpuRenderer::new(scene)),
                accumulated: None,
            }),
        }
    }

    pub(crate) fn describe(&self) -> String {
        match self {
            Self::Vulkan { renderer, .. } => format!("vulkan ({})", renderer.device_name()),
            Self::Cpu { .. } => "cpu".into(),
        }
    }

    pub(crate) fn presentation(&self) -> Presentation {
        match self {
            Self::Vulkan { .. } => Presentation::Direct,
            Self::Cpu { .. } => Presentation::HostCopy,
        }
    }

    pub(crate) fn is_cpu(&self) -> bool {
        matches!(self, Self::Cpu { .. })
    }

    /// The renderer's validation counter; it keeps counting through the renderer's drop.
    pub(crate) fn message_counter(&self) -> Option<Arc<MessageCounter>> {
        match self {
            Self::Vulkan { renderer, .. } => Some(renderer.message_counter()),
            Self::Cpu { .. } => None,
        }
    }

    /// Starts presenting to `window` (which outlives it until `close_window`).
    pub(crate) fn attach_window(
        &mut self,
        display: RawDisplayHandle,
        window: RawWindowHandle,
        size: (u32, u32),
        vsync: bool,
        validation: bool,
    ) -> Result<(), ViewerError> {
        match self {
            Self::Vulkan { window: target, renderer, .. } => {
                *target = Some(Box::new(WindowTarget::new(renderer, display, window, size, vsync)?));
            }
            Self::Cpu { presenter, .. } => {
                *presenter = Some(Box::new(Presenter::new(display, window, size, vsync, validation)?));
            }
        }
        Ok(())
    }

    /// The host presenter's own validation counter (the direct path has none of its own).
    pub(crate) fn presenter_messages(&self) -> Option<Arc<MessageCounter>> {
        match self {
            Self::Cpu { presenter: Some(presenter), .. } => Some(presenter.message_counter()),
            _ => None,
        }
    }

    /// Tears the presentation down while the window still exists.
    pub(crate) fn close_window(&mut self) {
        match self {
            Self::Vulkan { window, .. } => *window = None,
            Self::Cpu { presenter, .. } => *presenter = None,
        }
    }

    pub(crate) fn resize(&mut self, width: u32, height: u32) {
        match self {
            Self::Vulkan { window: Some(window), .. } => window.resize(width, height),
            Self::Cpu { presenter: Some(presenter), .. } => presenter.frames().resize(width, height),
            _ => {}
        }
    }

    /// Flips vsync; the new state, `None` before the window opened.
    pub(crate) fn toggle_vsync(&mut self) -> Option<bool> {
        match self {
            Self::Vulkan { window: Some(window), .. } => {
                window.set_vsync(!window.vsync());
                Some(window.vsync())
            }
            Self::Cpu { presenter: Some(presenter), .. } => {
                let frames = presenter.frames();
                frames.set_vsync(!frames.vsync());
                Some(frames.vsync())
            }
            _ => None,
        }
    }

    /// Draws `scene` (its camera and lights as they are now) with `settings` into the window;
    /// `keep` also returns the frame on the direct path (screenshots).
    pub(crate) fn draw(
        &mut self,
        scene: &Scene,
        settings: &RenderSettings,
        keep: bool,
    ) -> Result<Drawn, ViewerError> {
        self.update_scene(scene)?;
        match self {
            Self::Vulkan { window: Some(window), prepared, renderer, .. } => {
                let read_back = if keep { ReadBack::Keep } else { ReadBack::No };
                let presented = window.present(renderer, prepared, settings, read_back)?;
                let shown = presented == pointray_vulkan::Presented::Shown;
                let frame =
                    if keep && shown { Some(image_from_display(&window.shown_rgba8()?)) } else { None };
                Ok(Drawn { shown, frame })
            }
            Self::Vulkan { window: None, .. } => Ok(Drawn { shown: false, frame: None }),
            Self::Cpu { presenter, renderer, accumulated } => {
                let frame = continue_mean(accumulated.take(), renderer.render(settings), settings);
                *accumulated = Some(frame.clone());
                let shown = match presenter {
                    Some(presenter) => show_on_host(presenter, &frame)?,
                    None => false,
                };
                Ok(Drawn { shown, frame: Some(frame) })
            }
        }
    }

    /// Shows an already rendered frame again (the host path re-presents after a resize).
    pub(crate) fn show_again(&mut self, frame: &RenderedImage) -> Result<bool, ViewerError> {
        match self {
            Self::Cpu { presenter: Some(presenter), .. } => show_on_host(presenter, frame),
            _ => Ok(false),
        }
    }

    /// Moves the camera to `scene`'s and, where the scene's point sets stream, loads the tiles
    /// it needs for at most `limit` and evicts those it no longer does; `None` where nothing
    /// streams.
    pub(crate) fn stream_tiles(
        &mut self,
        scene: &Scene,
        aspect: f32,
        limit: Option<Duration>,
    ) -> Result<Option<TileResidency>, ViewerError> {
        match self {
            Self::Vulkan { prepared, .. } => {
                prepared.camera = scene.camera;
                Ok(prepared.stream_tiles(aspect, limit)?)
            }
            Self::Cpu { .. } => Ok(None),
        }
    }

    /// Sets the camera and the lights. Neither is in an acceleration structure: changing
    /// them rebuilds nothing.
    fn update_scene(&mut self, scene: &Scene) -> Result<(), ViewerError> {
        match self {
            Self::Vulkan { prepared, lights, .. } => {
                prepared.camera = scene.camera;
                if *lights != scene.lights {
                    prepared.set_lights(&scene.lights)?;
                    lights.clone_from(&scene.lights);
                }
            }
            Self::Cpu { renderer, .. } => {
                renderer.set_camera(scene.camera);
                renderer.set_lights(scene.lights.clone());
            }
        }
        Ok(())
    }
}

/// As `render` prepares a scene: point sets over the GPU memory budget go to boxes of several
/// patches, and where they still do not fit they stream, their tiles following the camera of
/// an image of `view_size` pixels, those it does not hold in full drawn coarse.
fn streaming_layout(view_size: (u32, u32)) -> SceneLayout {
    let (width, height) = view_size;
    SceneLayout::for_frames(&RenderSettings { width, height, ..RenderSettings::default() })
}

/// The host path: the frame's bytes, scaled to the swapchain, uploaded and presented.
fn show_on_host(presenter: &mut Presenter, frame: &RenderedImage) -> Result<bool, ViewerError> {
    let Some((extent, order)) = presenter.target()? else { return Ok(false) };
    let bytes = image_bytes(frame, extent.width, extent.height, order);
    Ok(presenter.present(&bytes)? == pointray_vulkan::Presented::Shown)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use pointray_scene::{LoadOptions, load_demo};

    use super::*;
    use pointray_render::BackendError;
    use pointray_scene::orbit_camera;

    /// The demo seen from a quarter turn round, lit by two lights from the other side.
    fn moved(scene: &Scene) -> Scene {
        let lights = vec![
            Light::point(Vec3::new(-2.0, 3.0, -2.5), Vec3::ONE, 0.8),
            Light::Directional { direction: Vec3::new(0.5, -1.0, 0.3), color: Vec3::ONE, intensity: 0.3 },
        ];
        Scene { camera: orbit_camera(&scene.camera, 1, 4, 360.0), lights, ..scene.clone() }
    }

    fn fresh_render(backend: BackendChoice, scene: &Scene, settings: &RenderSettings) -> RenderedImage {
        match backend {
            BackendChoice::Cpu => pointray_cpu::render(scene, settings),
            _ => {
                let renderer = VulkanRenderer::with_validation(DeviceSelector::Auto, true).expect("reopens");
                let frame = renderer.render(scene, settings).expect("a fresh render");
                assert_eq!(renderer.validation_messages(), 0, "validation messages (printed above)");
                frame
            }
        }
    }

    /// The source's renderer with its scene updated to `scene`, into host memory (the
    /// windowless twin of `draw`).
    fn render(source: &mut FrameSource, scene: &Scene, settings: &RenderSettings) -> RenderedImage {
        source.update_scene(scene).expect("the scene updates");
        match source {
            FrameSource::Vulkan { prepared, renderer, .. } => {
                renderer.trace(prepared, settings).expect("traces")
            }
            FrameSource::Cpu { renderer, .. } => renderer.render(settings),
        }
    }

    /// A source built for one view, then moved, draws what a source built for the new view
    /// draws: the camera and the lights reach every kind of ray without a rebuild.
    #[test]
    fn moved_camera_and_lights_match_a_fresh_render_on_both_backends() {
        let loaded = load_demo(&LoadOptions::default()).expect("the demo scene loads");
        let settings = RenderSettings { width: 64, height: 48, ..loaded.settings };
        let moved = moved(&loaded.scene);
        for backend in [BackendChoice::Cpu, BackendChoice::Vulkan] {
            let mut source = match FrameSource::open(
                backend,
                &DeviceSelector::Auto,
                DeviceOptions::VALIDATED,
                &loaded.scene,
                (settings.width, settings.height),
                None,
            ) {
                Ok(source) => source,
                Err(ViewerError::Backend(BackendError::VulkanUnavailable(error))) if error.is_no_device() => {
                    pointray_test_support::skip_without_device(&error);
                    continue;
                }
                Err(error) => panic!("{backend:?} does not open: {error}"),
            };
            let first = render(&mut source, &loaded.scene, &settings);
            let after = render(&mut source, &moved, &settings);
            assert_ne!(first.color, after.color, "{backend:?}: the view did not change");
            let fresh = fresh_render(backend, &moved, &settings);
            assert!(after.color == fresh.color, "{backend:?}: the moved view differs from a fresh render");
            let messages = source.message_counter().map_or(0, |counter| counter.count());
            assert_eq!(messages, 0, "validation messages (printed above)");
        }
    }
}
