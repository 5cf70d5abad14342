//! A procedural sun and sky as an equirectangular map, for scenes that want an environment
//! with no data file: a blue sky brightening toward the horizon and around the sun, a dark
//! ground below the horizon, and a sun disk whose irradiance is given.

use core::f32::consts::PI;

use glam::{Vec2, Vec3};
use pointray_kernels::{EnvironmentMap, environment_direction};

/// Texels across the map; the height is half. A 2-degree sun spans about 11 texels.
pub const SUN_SKY_WIDTH: u32 = 1024;

const ZENITH: Vec3 = Vec3::new(0.22, 0.4, 0.85);
const HORIZON: Vec3 = Vec3::new(0.8, 0.87, 1.0);
const GROUND: Vec3 = Vec3::new(0.16, 0.14, 0.12);
const SUN_COLOR: Vec3 = Vec3::new(1.0, 0.93, 0.82);
/// Sub-samples on a side for texels that the sun's disk may touch.
const SUN_SUPERSAMPLING: u32 = 6;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunSky {
    /// Degrees above the horizon.
    pub sun_elevation_degrees: f32,
    /// Degrees from -z toward +x (the map's u times 360).
    pub sun_azimuth_degrees: f32,
    /// The disk's angular radius in degrees.
    pub sun_radius_degrees: f32,
    /// The sun's irradiance on a surface facing it, before the sky's own light.
    pub sun_intensity: f32,
    /// Scales the sky's and the ground's radiance (1: a zenith of about 0.4).
    pub sky_intensity: f32,
}

impl SunSky {
    pub fn sun_direction(&self) -> Vec3 {
        let (elevation, azimuth) =
            (self.sun_elevation_degrees.to_radians(), self.sun_azimuth_degrees.to_radians());
        Vec3::new(elevation.cos() * azimuth.sin(), elevation.sin(), -elevation.cos() * azimuth.cos())
    }

    /// The map, `SUN_SKY_WIDTH` texels wide.
    pub fn map(&self) -> EnvironmentMap {
        let (width, height) = (SUN_SKY_WIDTH, SUN_SKY_WIDTH / 2);
        // Directions of map coordinates, from a map without rotation.
        let grid = EnvironmentMap::new(2, 1, &[Vec3::ZERO; 2], 0.0);
        let texels: Vec<Vec3> =
            (0..width * height).map(|i| self.texel(&grid, i % width, i / width, width, height)).collect();
        EnvironmentMap::new(width, height, &texels, 0.0)
    }

    fn texel(&self, grid: &EnvironmentMap, x: u32, y: u32, width: u32, height: u32) -> Vec3 {
        let size = Vec2::new(1.0 / width as f32, 1.0 / height as f32);
        let corner = Vec2::new(x as f32, y as f32) * size;
        let centre = environment_direction(grid, corner + 0.5 * size);
        let sun = self.sun_direction();
        let radius = self.sun_radius_degrees.to_radians();
        // A texel spans at most 2π / width on the sphere, less near the poles.
        let reach = radius + 2.0 * PI / width as f32;
        let sky = self.sky(centre, sun);
        if centre.dot(sun) < reach.cos() {
            return sky;
        }
        let n = SUN_SUPERSAMPLING;
        let covered = (0..n * n)
            .filter(|i| {
                let offset = Vec2::new((i % n) as f32 + 0.5, (i / n) as f32 + 0.5) / n as f32;
                environment_direction(grid, corner + offset * size).dot(sun) >= radius.cos()
            })
            .count();
        let solid_angle = 2.0 * PI * (1.0 - radius.cos());
        sky + SUN_COLOR * (self.sun_intensity / solid_angle) * (covered as f32 / (n * n) as f32)
    }

    fn sky(&self, direction: Vec3, sun: Vec3) -> Vec3 {
        if direction.y < 0.0 {
            return GROUND * self.sky_intensity;
        }
        let blue = HORIZON.lerp(ZENITH, direction.y.sqrt());
        let glow = direction.dot(sun).max(0.0).powi(8);
        self.sky_intensity * (blue + 0.6 * glow * HORIZON)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pointray_kernels::{environment_radiance, environment_sample};

    fn noon() -> SunSky {
        SunSky {
            sun_elevation_degrees: 60.0,
            sun_azimuth_degrees: 30.0,
            sun_radius_degrees: 2.0,
            sun_intensity: 5.0,
            sky_intensity: 0.0,
        }
    }

    #[test]
    fn the_sun_gives_its_irradiance_to_a_surface_facing_it() {
        let sky = noon();
        let map = sky.map();
        let sun = sky.sun_direction();
        assert!(environment_radiance(&map, sun).x > 100.0);
        // Irradiance on the plane facing the sun, estimated by drawing from the map.
        let count = 4096;
        let irradiance: f32 = (0..count)
            .map(|i| {
                let u = Vec2::new((i % 64) as f32 + 0.5, (i / 64) as f32 + 0.5) / 64.0;
                let drawn = environment_sample(&map, u);
                drawn.radiance.x * drawn.direction.dot(sun).max(0.0) / drawn.pdf
            })
            .sum::<f32>()
            / count as f32;
        assert!(
            (irradiance - sky.sun_intensity * SUN_COLOR.x).abs() < 0.05 * sky.sun_intensity,
            "{irradiance}"
        );
    }

    #[test]
    fn the_ground_is_darker_than_the_sky() {
        let sky = SunSky { sky_intensity: 1.0, ..noon() };
        let map = sky.map();
        let down = environment_radiance(&map, Vec3::NEG_Y);
        let up = environment_radiance(&map, Vec3::Y);
        assert!(down.length() < 0.5 * up.length(), "{down} {up}");
    }
}
