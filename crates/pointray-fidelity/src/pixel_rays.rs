//! The primary ray of a image's pixel, as both renderers cast it with one sample a pixel: the
//! depth AOV is the distance along it, so it rebuilds each hit from the image alone.

use glam::UVec2;
use pointray_kernels::{Ray, camera_ray, sample_jitter};
use pointray_scene::{Camera, RenderedImage};

/// The primary rays of one image rendered by one camera.
pub struct PixelRays {
    camera: Camera,
    size: UVec2,
}

impl PixelRays {
    pub fn new(camera: &Camera, image: &RenderedImage) -> Self {
        Self { camera: *camera, size: UVec2::new(image.width, image.height) }
    }

    /// The ray through `pixel`, an index in row order.
    pub fn ray(&self, pixel: usize) -> Ray {
        let width = self.size.x as usize;
        let coordinates = UVec2::new((pixel % width) as u32, (pixel / width) as u32);
        camera_ray(&self.camera, self.size, coordinates, sample_jitter(0))
    }
}
