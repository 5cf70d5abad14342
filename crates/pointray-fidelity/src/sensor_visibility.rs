//! Which mesh pixels a scan's sensor could have seen: a scan holds nothing of the roofs it
//! looked past or the street behind a parked car, so a view from above that counts those as
//! holes measures the sensor, not the surface. A pixel counts as seen when its mesh point
//! lies in the sensor's elevation band and range, and nothing of the mesh stands between.

use glam::Vec3;
use pointray_cpu::CpuRenderer;
use pointray_kernels::Ray;
use pointray_scene::{Camera, PatchAcceptance, RenderedImage, Scene};
use rayon::prelude::*;

use crate::SensorPose;
use crate::pixel_rays::PixelRays;

/// A return's elevation may stray this far past the band the returns span (beam width).
const ELEVATION_MARGIN_DEGREES: f32 = 0.5;
/// How much nearer than the mesh point a blocking surface must be, as a fraction of the
/// range plus an absolute term in scene units: the point's own triangle, met at a grazing
/// angle, must not hide it.
const BLOCKING_FRACTION: f32 = 0.01;
const BLOCKING_ABSOLUTE: f32 = 0.02;

/// The mesh, as the sensor saw it.
pub struct SensorVisibility {
    mesh: CpuRenderer,
    sensor: SensorPose,
    up: Vec3,
}

impl SensorVisibility {
    /// `mesh_scene` holds the mesh alone; `up` is the scan's unit up axis.
    pub fn new(mesh_scene: &Scene, sensor: SensorPose, up: Vec3) -> Self {
        Self { mesh: CpuRenderer::new(mesh_scene), sensor, up }
    }

    /// For each pixel of `image` (the mesh rendered by `camera`), whether the sensor could
    /// have seen the mesh point there; pixels off the mesh are `false`.
    pub fn seen_pixels(&self, image: &RenderedImage, camera: &Camera) -> Vec<bool> {
        let rays = PixelRays::new(camera, image);
        (0..image.pixel_count())
            .into_par_iter()
            .map(|pixel| {
                if image.instance_id[pixel] == RenderedImage::MISS {
                    return false;
                }
                self.sees(rays.ray(pixel).at(image.depth[pixel]))
            })
            .collect()
    }

    /// Whether `point` lies in the sensor's band and range, in its line of sight.
    pub fn sees(&self, point: Vec3) -> bool {
        let to_point = point - self.sensor.position;
        let range = to_point.length();
        if !(range > 0.0 && range <= self.sensor.max_range) {
            return false;
        }
        let direction = to_point / range;
        let elevation = direction.dot(self.up).clamp(-1.0, 1.0).asin().to_degrees();
        let [low, high] = self.sensor.elevation_degrees;
        if elevation < low - ELEVATION_MARGIN_DEGREES || elevation > high + ELEVATION_MARGIN_DEGREES {
            return false;
        }
        let clear_until = range * (1.0 - BLOCKING_FRACTION) - BLOCKING_ABSOLUTE;
        let ray = Ray::new(self.sensor.position, direction);
        clear_until <= 0.0 || self.mesh.first_hit(&ray, 0.0, clear_until, PatchAcceptance::Disk).is_none()
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use glam::Affine3A;
    use pointray_io::TriangleMesh;
    use pointray_scene::{Background, Geometry, Material, SceneObject};

    use super::*;

    /// A road 200 m square at z = 0 and a wall across it at x = 30, 10 m high.
    fn street_scene() -> Scene {
        let mut mesh = TriangleMesh {
            positions: vec![
                Vec3::new(-100.0, -100.0, 0.0),
                Vec3::new(100.0, -100.0, 0.0),
                Vec3::new(100.0, 100.0, 0.0),
                Vec3::new(-100.0, 100.0, 0.0),
                Vec3::new(30.0, -100.0, 0.0),
                Vec3::new(30.0, 100.0, 0.0),
                Vec3::new(30.0, 100.0, 10.0),
                Vec3::new(30.0, -100.0, 10.0),
            ],
            triangles: Vec::new(),
        };
        mesh.push_polygon(&[0, 1, 2, 3]);
        mesh.push_polygon(&[4, 5, 6, 7]);
        let object = SceneObject {
            name: "street".into(),
            transform: Affine3A::IDENTITY,
            material: Material::default(),
            geometry: Geometry::Mesh(Arc::new(mesh)),
        };
        let camera =
            Camera { position: Vec3::Z, look_at: Vec3::ZERO, up: Vec3::Y, vertical_fov_degrees: 40.0 };
        Scene { camera, lights: Vec::new(), background: Background::Solid(Vec3::ZERO), objects: vec![object] }
    }

    #[test]
    fn the_sensor_sees_its_band_and_range_up_to_the_first_wall() {
        let sensor = SensorPose {
            position: Vec3::new(0.0, 0.0, 1.73),
            elevation_degrees: [-24.3, 2.0],
            max_range: 100.0,
        };
        let visibility = SensorVisibility::new(&street_scene(), sensor, Vec3::Z);
        assert!(visibility.sees(Vec3::new(10.0, 0.0, 0.0)), "the road ahead");
        assert!(visibility.sees(Vec3::new(-10.0, 5.0, 0.0)), "the road behind");
        assert!(!visibility.sees(Vec3::new(1.5, 0.0, 0.0)), "under the lowest beam");
        assert!(visibility.sees(Vec3::new(30.0, 0.0, 1.0)), "the wall's foot");
        assert!(!visibility.sees(Vec3::new(30.0, 0.0, 9.0)), "above the highest beam");
        assert!(!visibility.sees(Vec3::new(40.0, 0.0, 0.0)), "behind the wall");
        assert!(!visibility.sees(Vec3::new(-99.0, 99.0, 0.0)), "out of range");
    }
}
