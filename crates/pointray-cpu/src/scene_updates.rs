//! What may change between frames of a built renderer: the camera and the lights. Neither
//! is part of any BVH (the camera only makes primary rays, the lights only aim shadow rays),
//! so changing them costs nothing; a change of geometry needs a new `CpuRenderer`.

use pointray_scene::{Camera, Light};

use crate::renderer::CpuRenderer;

impl CpuRenderer {
    /// The camera of the next frames.
    pub fn set_camera(&mut self, camera: Camera) {
        self.scene.camera = camera;
    }

    /// The lights of the next frames, replacing all of the current ones.
    pub fn set_lights(&mut self, lights: Vec<Light>) {
        self.scene.lights = lights;
    }
}
