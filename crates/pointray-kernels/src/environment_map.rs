//! An equirectangular environment map: its radiance in a direction, and directions drawn in
//! proportion to its luminance, with their densities. Twin of `shaders/environment_map.glsl`.
//!
//! The map's conventions are Mitsuba 3's, so that one file lights both renderers alike: +y
//! is up, the top row looks straight up, and the map's u runs with `atan2(x, -z)`. Each
//! texel is constant over its rectangle in (u, v), and texels are drawn with probability
//! proportional to their luminance times the sine of their row's polar angle (the solid
//! angle they cover), so the density is proportional to the radiance wherever that is grey.

use core::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::LightSample;
use crate::distribution::{cumulative, sample_cumulative};

/// A map ready to be drawn from. Its data is laid out as the GPU reads it.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    width: u32,
    height: u32,
    /// Turns about +y: the map's u is the direction's u plus this.
    rotation: f32,
    /// Radiance, row-major from the top row; w is unused.
    texels: Vec<[f32; 4]>,
    /// The rows' cumulative distribution (`height + 1` values from 0 to 1), then each row's
    /// over its texels (`width + 1` values each).
    distribution: Vec<f32>,
    /// Every texel black: there is nothing to draw.
    black: bool,
}

const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

impl EnvironmentMap {
    /// `radiance` holds `width * height` texels, row-major from the top row, each finite
    /// and non-negative (checked by whoever read them); `rotation` is in turns about +y.
    pub fn new(width: u32, height: u32, radiance: &[Vec3], rotation: f32) -> Self {
        assert_eq!(radiance.len(), width as usize * height as usize, "one texel per pixel");
        let texels = radiance.iter().map(|t| [t.x, t.y, t.z, 0.0]).collect();
        let black = radiance.iter().all(|&t| t == Vec3::ZERO);
        let weights: Vec<f64> = radiance
            .chunks(width as usize)
            .enumerate()
            .flat_map(|(row, texels)| {
                let sin_theta = (PI * (row as f32 + 0.5) / height as f32).sin();
                texels.iter().map(move |t| f64::from(t.dot(LUMINANCE).max(0.0) * sin_theta))
            })
            .collect();
        let row_sums: Vec<f64> = weights.chunks(width as usize).map(|row| row.iter().sum()).collect();
        let mut distribution = cumulative(&row_sums);
        for row in weights.chunks(width as usize) {
            distribution.extend(cumulative(row));
        }
        Self { width, height, rotation, texels, distribution, black }
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    pub fn rotation(&self) -> f32 {
        self.rotation
    }

    pub fn texels(&self) -> &[[f32; 4]] {
        &self.texels
    }

    pub fn distribution(&self) -> &[f32] {
        &self.distribution
    }

    /// Whether every texel is black, so that there is nothing to draw.
    pub fn is_black(&self) -> bool {
        self.black
    }

    fn texel(&self, x: u32, y: u32) -> Vec3 {
        let [r, g, b, _] = self.texels[(y * self.width + x) as usize];
        Vec3::new(r, g, b)
    }
}

/// The map coordinates (u, v) in [0, 1)² of a unit direction.
pub fn environment_uv(map: &EnvironmentMap, direction: Vec3) -> Vec2 {
    let u = direction.x.atan2(-direction.z) * (0.5 / PI) + map.rotation;
    let v = direction.y.clamp(-1.0, 1.0).acos() * (1.0 / PI);
    Vec2::new(u - u.floor(), v)
}

/// The unit direction at map coordinates `uv`.
pub fn environment_direction(map: &EnvironmentMap, uv: Vec2) -> Vec3 {
    let phi = 2.0 * PI * (uv.x - map.rotation);
    let theta = PI * uv.y;
    Vec3::new(phi.sin() * theta.sin(), theta.cos(), -phi.cos() * theta.sin())
}

/// The texel holding map coordinates `uv`.
fn environment_texel(map: &EnvironmentMap, uv: Vec2) -> (u32, u32) {
    let x = ((uv.x * map.width as f32) as u32).min(map.width - 1);
    let y = ((uv.y * map.height as f32) as u32).min(map.height - 1);
    (x, y)
}

/// The radiance arriving from a unit direction.
pub fn environment_radiance(map: &EnvironmentMap, direction: Vec3) -> Vec3 {
    let (x, y) = environment_texel(map, environment_uv(map, direction));
    map.texel(x, y)
}

/// The density over (u, v) of texel (x, y): its share of the draws over its area.
fn texel_density(map: &EnvironmentMap, x: u32, y: u32) -> f32 {
    let row = &map.distribution[(map.height + 1 + y * (map.width + 1)) as usize..];
    let row_share = map.distribution[y as usize + 1] - map.distribution[y as usize];
    let texel_share = row[x as usize + 1] - row[x as usize];
    row_share * texel_share * (map.width * map.height) as f32
}

/// The density per steradian with which `environment_sample` draws a unit direction.
pub fn environment_pdf(map: &EnvironmentMap, direction: Vec3) -> f32 {
    let sin_theta = (1.0 - direction.y * direction.y).max(0.0).sqrt();
    if sin_theta == 0.0 {
        return 0.0;
    }
    let (x, y) = environment_texel(map, environment_uv(map, direction));
    texel_density(map, x, y) / (2.0 * PI * PI * sin_theta)
}

/// The `count` intervals of the distribution that starts at `offset`, searched for `u`.
fn sample_part(map: &EnvironmentMap, offset: u32, count: u32, u: f32) -> (u32, f32) {
    sample_cumulative(&map.distribution[offset as usize..=(offset + count) as usize], u)
}

/// A direction drawn from the map by two uniform numbers, with the radiance from it and its
/// density (0 at the poles, where the density has no finite value).
pub fn environment_sample(map: &EnvironmentMap, u: Vec2) -> LightSample {
    let (y, fraction_y) = sample_part(map, 0, map.height, u.y);
    let (x, fraction_x) = sample_part(map, map.height + 1 + y * (map.width + 1), map.width, u.x);
    let uv =
        Vec2::new((x as f32 + fraction_x) / map.width as f32, (y as f32 + fraction_y) / map.height as f32);
    let direction = environment_direction(map, uv);
    let sin_theta = (PI * uv.y).sin();
    let pdf = if sin_theta > 0.0 { texel_density(map, x, y) / (2.0 * PI * PI * sin_theta) } else { 0.0 };
    LightSample { direction, distance: f32::INFINITY, radiance: map.texel(x, y), pdf }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{UNIFORM_SPHERE_PDF, uniform_sphere};

    /// A dim sky with a bright patch: most of the draws go to the patch.
    fn sun_map() -> EnvironmentMap {
        let (width, height) = (64, 32);
        let texels: Vec<Vec3> = (0..width * height)
            .map(|i| {
                let (x, y) = (i % width, i / width);
                let sun = (20..23).contains(&x) && (9..11).contains(&y);
                if sun { Vec3::new(400.0, 380.0, 300.0) } else { Vec3::new(0.2, 0.3, 0.6) * (y as f32 / 8.0) }
            })
            .collect();
        EnvironmentMap::new(width, height, &texels, 0.15)
    }

    /// Random numbers from a fixed generator, so that the tests are deterministic.
    fn numbers(count: usize) -> impl Iterator<Item = Vec2> {
        let mut state = 0x9e37_79b9_u32;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            (state >> 8) as f32 / (1 << 24) as f32
        };
        (0..count).map(move |_| Vec2::new(next(), next()))
    }

    #[test]
    fn map_coordinates_and_directions_are_inverse() {
        let map = sun_map();
        for u in numbers(1000) {
            let direction = environment_direction(&map, u);
            assert!((direction.length() - 1.0).abs() < 1e-5);
            let back = environment_uv(&map, direction);
            let wrapped = (back.x - u.x).abs().min(1.0 - (back.x - u.x).abs());
            assert!(wrapped < 1e-4 && (back.y - u.y).abs() < 1e-4, "{u} -> {direction} -> {back}");
        }
    }

    #[test]
    fn the_top_row_looks_up_and_u_follows_mitsuba() {
        let map = EnvironmentMap::new(4, 2, &[Vec3::ONE; 8], 0.0);
        assert!(environment_direction(&map, Vec2::new(0.3, 0.0)).abs_diff_eq(Vec3::Y, 1e-6));
        // Mitsuba's envmap: u = atan2(x, -z) / 2π, so u = 0 looks along -z and u = 1/4 along +x.
        assert!(environment_direction(&map, Vec2::new(0.0, 0.5)).abs_diff_eq(Vec3::NEG_Z, 1e-6));
        assert!(environment_direction(&map, Vec2::new(0.25, 0.5)).abs_diff_eq(Vec3::X, 1e-6));
    }

    #[test]
    fn the_density_integrates_to_one_over_the_sphere() {
        let map = sun_map();
        let count = 400_000;
        let integral: f32 = numbers(count).map(|u| environment_pdf(&map, uniform_sphere(u))).sum::<f32>()
            / (count as f32 * UNIFORM_SPHERE_PDF);
        assert!((integral - 1.0).abs() < 0.02, "{integral}");
    }

    #[test]
    fn a_drawn_direction_has_the_density_and_radiance_found_by_looking_it_up() {
        let map = sun_map();
        for u in numbers(5000) {
            let drawn = environment_sample(&map, u);
            assert!(drawn.pdf > 0.0, "{u}");
            let pdf = environment_pdf(&map, drawn.direction);
            assert!((pdf / drawn.pdf - 1.0).abs() < 2e-3, "{u}: {pdf} against {}", drawn.pdf);
            assert_eq!(environment_radiance(&map, drawn.direction), drawn.radiance, "{u}");
        }
    }

    #[test]
    fn drawing_from_the_map_estimates_its_irradiance_with_less_noise_than_uniform_draws() {
        let map = sun_map();
        let count = 20_000;
        let up_irradiance = |direction: Vec3, radiance: Vec3, pdf: f32| {
            if pdf > 0.0 { radiance.dot(LUMINANCE) * direction.y.max(0.0) / pdf } else { 0.0 }
        };
        let drawn: Vec<f32> = numbers(count)
            .map(|u| {
                let s = environment_sample(&map, u);
                up_irradiance(s.direction, s.radiance, s.pdf)
            })
            .collect();
        let uniform: Vec<f32> = numbers(count)
            .map(|u| {
                let direction = uniform_sphere(u);
                up_irradiance(direction, environment_radiance(&map, direction), UNIFORM_SPHERE_PDF)
            })
            .collect();
        let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
        let variance = |v: &[f32]| {
            let m = mean(v);
            v.iter().map(|x| (x - m) * (x - m)).sum::<f32>() / v.len() as f32
        };
        let (a, b) = (mean(&drawn), mean(&uniform));
        let error = 4.0 * (variance(&uniform) / count as f32).sqrt();
        assert!((a - b).abs() < error, "importance {a}, uniform {b} ± {error}");
        assert!(
            variance(&drawn) * 20.0 < variance(&uniform),
            "{} against {}",
            variance(&drawn),
            variance(&uniform)
        );
    }

    #[test]
    fn rows_without_light_are_never_drawn() {
        let mut texels = vec![Vec3::ZERO; 16 * 8];
        texels[3 * 16 + 5] = Vec3::ONE;
        let map = EnvironmentMap::new(16, 8, &texels, 0.0);
        for u in numbers(2000) {
            let drawn = environment_sample(&map, u);
            assert_eq!(drawn.radiance, Vec3::ONE, "{u}");
        }
        assert!(!map.is_black());
        assert!(EnvironmentMap::new(2, 1, &[Vec3::ZERO; 2], 0.0).is_black());
    }
}
