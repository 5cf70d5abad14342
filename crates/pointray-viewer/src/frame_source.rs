//! Where frames come from: the Vulkan ray tracer or the CPU renderer. Either builds its
//! acceleration structures once; each frame only sets the camera and the lights.

use pointray_cpu::CpuRenderer;
use pointray_scene::{Frame, Light, RenderSettings, Scene};
use pointray_vulkan::{DeviceSelector, PixelOutput, PreparedScene, TraceTarget, VulkanRenderer};

use crate::error::ViewerError;

/// Which renderer draws the frames; as `pointray render --backend`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RenderBackend {
    /// A hardware ray-tracing GPU if there is one, else the CPU renderer (CPU Vulkan drivers
    /// such as lavapipe are slower than the CPU renderer, as for `pointray render`).
    #[default]
    Auto,
    Vulkan,
    Cpu,
}

pub(crate) enum FrameSource {
    Vulkan {
        // Before the renderer: their GPU objects go first.
        /// Kept across frames, so its buffers are allocated again only when the size changes.
        target: Box<TraceTarget>,
        prepared: Box<PreparedScene>,
        /// The lights `prepared` shades with.
        lights: Vec<Light>,
        renderer: Box<VulkanRenderer>,
    },
    Cpu(Box<CpuRenderer>),
}

impl FrameSource {
    pub(crate) fn open(
        choice: RenderBackend,
        device: &DeviceSelector,
        validation: bool,
        scene: &Scene,
    ) -> Result<Self, ViewerError> {
        let open = || VulkanRenderer::with_validation(device.clone(), validation);
        let renderer = match choice {
            RenderBackend::Cpu => None,
            RenderBackend::Vulkan => Some(open()?),
            RenderBackend::Auto => {
                open().ok().filter(|r| !r.device_info().device_type.to_ascii_lowercase().contains("cpu"))
            }
        };
        match renderer {
            Some(renderer) => Ok(Self::Vulkan {
                target: Box::new(TraceTarget::new(PixelOutput::Aovs)),
                prepared: Box::new(renderer.prepare(scene)?),
                lights: scene.lights.clone(),
                renderer: Box::new(renderer),
            }),
            None => Ok(Self::Cpu(Box::new(CpuRenderer::new(scene)))),
        }
    }

    pub(crate) fn describe(&self) -> String {
        match self {
            Self::Vulkan { renderer, .. } => format!("vulkan ({})", renderer.device_name()),
            Self::Cpu(_) => "cpu".into(),
        }
    }

    pub(crate) fn is_cpu(&self) -> bool {
        matches!(self, Self::Cpu(_))
    }

    pub(crate) fn vulkan_device_name(&self) -> Option<&str> {
        match self {
            Self::Vulkan { renderer, .. } => Some(renderer.device_name()),
            Self::Cpu(_) => None,
        }
    }

    pub(crate) fn validation_messages(&self) -> u32 {
        match self {
            Self::Vulkan { renderer, .. } => renderer.validation_messages(),
            Self::Cpu(_) => 0,
        }
    }

    /// Renders `scene` (its camera and lights as they are now) with `settings`.
    pub(crate) fn render(&mut self, scene: &Scene, settings: &RenderSettings) -> Result<Frame, ViewerError> {
        match self {
            // Neither the camera nor the lights are in an acceleration structure: changing
            // them rebuilds nothing.
            Self::Vulkan { target, prepared, lights, renderer } => {
                prepared.camera = scene.camera;
                if *lights != scene.lights {
                    prepared.set_lights(&scene.lights)?;
                    lights.clone_from(&scene.lights);
                }
                renderer.trace_into(prepared, settings, target)?;
                Ok(target.frame()?)
            }
            Self::Cpu(renderer) => {
                renderer.set_camera(scene.camera);
                renderer.set_lights(scene.lights.clone());
                Ok(renderer.render(settings))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use pointray_scene::{LoadOptions, load_demo};
    use pointray_vulkan::VulkanError;

    use super::*;
    use crate::orbit::orbit_camera;

    /// The demo seen from a quarter turn round, lit by two lights from the other side.
    fn moved(scene: &Scene) -> Scene {
        let lights = vec![
            Light::Point { position: Vec3::new(-2.0, 3.0, -2.5), color: Vec3::ONE, intensity: 0.8 },
            Light::Directional { direction: Vec3::new(0.5, -1.0, 0.3), color: Vec3::ONE, intensity: 0.3 },
        ];
        Scene { camera: orbit_camera(&scene.camera, 1, 4, 360.0), lights, ..scene.clone() }
    }

    fn fresh_render(backend: RenderBackend, scene: &Scene, settings: &RenderSettings) -> Frame {
        match backend {
            RenderBackend::Cpu => pointray_cpu::render(scene, settings),
            _ => {
                let renderer = VulkanRenderer::with_validation(DeviceSelector::Auto, true).expect("reopens");
                let frame = renderer.render(scene, settings).expect("a fresh render");
                assert_eq!(renderer.validation_messages(), 0, "validation messages (printed above)");
                frame
            }
        }
    }

    /// A source built for one view, then moved, draws what a source built for the new view
    /// draws: the camera and the lights reach every kind of ray without a rebuild.
    #[test]
    fn moved_camera_and_lights_match_a_fresh_render_on_both_backends() {
        let loaded = load_demo(&LoadOptions::default()).expect("the demo scene loads");
        let settings = RenderSettings { width: 64, height: 48, ..loaded.settings };
        let moved = moved(&loaded.scene);
        for backend in [RenderBackend::Cpu, RenderBackend::Vulkan] {
            let mut source = match FrameSource::open(backend, &DeviceSelector::Auto, true, &loaded.scene) {
                Ok(source) => source,
                Err(
                    error @ ViewerError::Renderer(
                        VulkanError::NoSuitableDevice(_)
                        | VulkanError::LoaderMissing(_)
                        | VulkanError::ValidationLayerMissing,
                    ),
                ) => {
                    assert!(!std::env::var("CI").is_ok_and(|v| v == "true"), "CI=true but {error}");
                    eprintln!("note: skipping {backend:?}, {error}");
                    continue;
                }
                Err(error) => panic!("{backend:?} does not open: {error}"),
            };
            let first = source.render(&loaded.scene, &settings).expect("the first view renders");
            let after = source.render(&moved, &settings).expect("the moved view renders");
            assert_ne!(first.color, after.color, "{backend:?}: the view did not change");
            let fresh = fresh_render(backend, &moved, &settings);
            assert!(after.color == fresh.color, "{backend:?}: the moved view differs from a fresh render");
            assert_eq!(source.validation_messages(), 0, "validation messages (printed above)");
        }
    }
}
